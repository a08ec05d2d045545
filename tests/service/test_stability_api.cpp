// The analysis "stability" through the facade: its options (strict, bounded, echoed) and its
// result (eigenvalues and modes at the scenario's speed, the stack's modes, the critical speed).

#include <doctest/doctest.h>

#include <cmath>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"
#include "service/analyses/stability.h"
#include "support/refused_options.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

void check_stability_rejected(const json& options, const std::string& pointer,
                              std::optional<std::string> bound, std::optional<std::string> unit) {
    test::check_refused_options("stability", options, pointer, bound, unit);
}

json run_stability(const json& scenario, const json& options) {
    const Outcome outcome =
        evaluate({{"analysis", "stability"}, {"scenario", scenario}, {"options", options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    return outcome.body;
}

}  // namespace

TEST_CASE("stability options: the defaults are resolved and echoed") {
    api::FieldErrors errors;
    const PreparedAnalysis prepared =
        prepare_stability(core::Scenario{}, json::object(), "/options", errors);
    CHECK(errors.empty());
    CHECK(prepared.resolved_options == json{{"speed_min_m_per_s", 1.0},
                                            {"speed_max_m_per_s", 60.0},
                                            {"speed_step_m_per_s", 0.5},
                                            {"relative_tolerance", 1e-4},
                                            {"critical_speed", true},
                                            {"detail", "full"}});
}

TEST_CASE("stability options: every bound is enforced, with its pointer, bound and unit") {
    check_stability_rejected({{"speed_min_m_per_s", 0.0}}, "/options/speed_min_m_per_s",
                             "[0.01, 100]", "m/s");
    check_stability_rejected({{"speed_max_m_per_s", 101}}, "/options/speed_max_m_per_s",
                             "[0.01, 100]", "m/s");
    check_stability_rejected({{"speed_step_m_per_s", 0}}, "/options/speed_step_m_per_s", "(0, 0.5]",
                             "m/s");
    check_stability_rejected({{"speed_step_m_per_s", 0.6}}, "/options/speed_step_m_per_s",
                             "(0, 0.5]", "m/s");
    check_stability_rejected({{"relative_tolerance", 0}}, "/options/relative_tolerance",
                             "[1e-08, 0.01]", "1");
    check_stability_rejected({{"relative_tolerance", 0.1}}, "/options/relative_tolerance",
                             "[1e-08, 0.01]", "1");
    check_stability_rejected({{"critical_speed", "yes"}}, "/options/critical_speed", std::nullopt,
                             std::nullopt);
    check_stability_rejected({{"speed_min_m_per_s", "1"}}, "/options/speed_min_m_per_s",
                             std::nullopt, std::nullopt);
    check_stability_rejected(json::array(), "/options", std::nullopt, std::nullopt);
    // The search range must not be empty; the error names speed_max with the range it allows.
    check_stability_rejected({{"speed_min_m_per_s", 30}, {"speed_max_m_per_s", 20}},
                             "/options/speed_max_m_per_s", "(30, 100]", "m/s");
    // A scan of more than max_scan_points speeds: the bound is the smallest step allowed.
    check_stability_rejected({{"speed_step_m_per_s", 0.001}}, "/options/speed_step_m_per_s",
                             "[0.0148, 0.5]", "m/s");
}

TEST_CASE(
    "stability options: unknown members are named, with a suggestion for a wrong unit suffix") {
    const Outcome outcome =
        evaluate({{"analysis", "stability"}, {"options", {{"speed_max_mps", 30}}}});
    const json error = test::error_at(outcome, "/options/speed_max_mps");
    REQUIRE(error.is_object());
    CHECK(error["detail"].get<std::string>().find("did you mean 'speed_max_m_per_s'") !=
          std::string::npos);
}

TEST_CASE(
    "stability at the scenario's speed: eigenvalues, least-damped mode and the stack's modes") {
    const json body = run_stability(json::object(), {{"critical_speed", false}});
    const json& result = body["result"];
    CHECK(result["status"] == "ok");
    CHECK(result["speed_m_per_s"] == 19.0);
    CHECK(result["stable"] == true);
    CHECK(result["critical_speed"].is_null());
    // k4 from the bite model: ~20 GN/m at the defaults (docs/model.md §5).
    CHECK(result["strip_stiffness_GN_per_m"].get<double>() > 5.0);
    CHECK(result["strip_stiffness_GN_per_m"].get<double>() < 50.0);

    // 6 positions, 6 velocities, the film and the span back tension; least damped first.
    const json& eigenvalues = result["eigenvalues"];
    REQUIRE(eigenvalues.size() == 14);
    for (std::size_t i = 1; i < eigenvalues.size(); ++i) {
        CHECK(eigenvalues[i - 1]["real_per_s"].get<double>() >=
              eigenvalues[i]["real_per_s"].get<double>());
    }
    CHECK(eigenvalues[0]["real_per_s"].get<double>() < 0.0);
    CHECK(eigenvalues[0]["real_per_s"] == result["max_growth_rate_per_s"]);

    // The ~104 Hz mode leads at 19 m/s (docs/model.md §7.3), lightly damped.
    const json& mode = result["least_damped_mode"];
    CHECK(mode["frequency_Hz"].get<double>() > 80.0);
    CHECK(mode["frequency_Hz"].get<double>() < 130.0);
    CHECK(mode["damping_ratio"].get<double>() > 0.0);
    CHECK(mode["damping_ratio"].get<double>() < 0.05);
    CHECK(mode["growth_rate_per_s"].get<double>() < 0.0);
    REQUIRE(mode["shape"].size() == 6);
    double largest = 0.0;
    for (const json& component : mode["shape"])
        largest = std::max(largest, component.get<double>());
    CHECK(largest == rollgap::test::approx(1.0));
    // The oscillatory modes, ascending in frequency, include it.
    CHECK(result["oscillatory_modes"].size() == 6);

    // The stack with the strip spring: six natural frequencies, ascending, shapes of six masses.
    const json& structure = result["structure"];
    CHECK(structure["strip_stiffness_GN_per_m"] == result["strip_stiffness_GN_per_m"]);
    REQUIRE(structure["natural_frequencies_Hz"].size() == 6);
    REQUIRE(structure["natural_mode_shapes"].size() == 6);
    for (std::size_t i = 0; i < 6; ++i) {
        CHECK(structure["natural_frequencies_Hz"][i].get<double>() > 0.0);
        if (i > 0)
            CHECK(structure["natural_frequencies_Hz"][i] >
                  structure["natural_frequencies_Hz"][i - 1]);
        CHECK(structure["natural_mode_shapes"][i].size() == 6);
    }
}

TEST_CASE("stability: the critical speed is found, and the stability verdict flips there") {
    // A narrow search range around the default's critical speed (~20 m/s) keeps the test fast.
    const json body =
        run_stability(json::object(), {{"speed_min_m_per_s", 15}, {"speed_max_m_per_s", 25}});
    const json& critical = body["result"]["critical_speed"];
    REQUIRE(critical["status"] == "found");
    const double v_c = critical["critical_speed_m_per_s"].get<double>();
    CHECK(v_c > 15.0);
    CHECK(v_c < 25.0);
    CHECK(v_c > 19.0);  // the default scenario runs just below it (stable above)
    const json& mode = critical["unstable_mode"];
    CHECK(mode["frequency_Hz"].get<double>() > 80.0);
    CHECK(mode["frequency_Hz"].get<double>() < 130.0);
    CHECK(std::abs(mode["growth_rate_per_s"].get<double>()) < 0.05);  // on the stability boundary

    // The scan: 21 speeds at 0.5 m/s, stable below v_c, unstable above.
    REQUIRE(critical["scan"].size() == 21);
    for (const json& point : critical["scan"]) {
        CAPTURE(point.dump());
        CHECK(point["steady_status"] == "ok");
        CHECK(point["stable"] == (point["speed_m_per_s"].get<double>() < v_c));
        CHECK((point["max_growth_rate_per_s"].get<double>() < 0.0) == point["stable"].get<bool>());
    }
    // Every damping branch has one speed, frequency and damping ratio per point.
    REQUIRE_FALSE(critical["damping_branches"].empty());
    for (const json& branch : critical["damping_branches"]) {
        CHECK(branch["speed_m_per_s"].size() == branch["frequency_Hz"].size());
        CHECK(branch["speed_m_per_s"].size() == branch["damping_ratio"].size());
    }

    // The linearisation at 0.99 v_c is stable, at 1.01 v_c unstable.
    const json below =
        run_stability({{"rolls", {{"speed_m_per_s", 0.99 * v_c}}}}, {{"critical_speed", false}});
    CHECK(below["result"]["stable"] == true);
    const json above =
        run_stability({{"rolls", {{"speed_m_per_s", 1.01 * v_c}}}}, {{"critical_speed", false}});
    CHECK(above["result"]["stable"] == false);
    CHECK(above["result"]["max_growth_rate_per_s"].get<double>() > 0.0);
}

TEST_CASE("stability: a range that starts unstable is a status, not a critical speed") {
    const json body =
        run_stability(json::object(), {{"speed_min_m_per_s", 25}, {"speed_max_m_per_s", 26}});
    const json& critical = body["result"]["critical_speed"];
    CHECK(critical["status"] == "unstable_at_lower_bound");
    CHECK(critical["critical_speed_m_per_s"].is_null());
    CHECK(critical["unstable_mode"].is_object());
}

TEST_CASE("stability: no steady state at the scenario's speed is a 200 result with a status") {
    // Without the limiting shear stress the default stand skids at high speed (docs/model.md §4).
    const json body = run_stability(
        {{"lubricant", {{"limiting_shear", false}}}, {"rolls", {{"speed_m_per_s", 60}}}},
        {{"critical_speed", false}});
    const json& result = body["result"];
    CHECK(result["status"] == "no_steady_state");
    CHECK(result["steady_status"] == "skidding");
    CHECK(result["stable"].is_null());
    CHECK(result["least_damped_mode"].is_null());
    CHECK(result["eigenvalues"].empty());
    CHECK(result["structure"].is_null());
}
