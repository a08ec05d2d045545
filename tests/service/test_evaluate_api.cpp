// The analysis "evaluate" (roll gap, stability, critical speed and amplitude at once; the HTTP
// service's default) and the facade's Control: cancellation and progress.

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/cli.h"
#include "service/evaluate.h"
#include "service/analyses/evaluation.h"
#include "support/refused_options.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

void check_evaluate_rejected(const json& options, const std::string& pointer,
                             std::optional<std::string> bound, std::optional<std::string> unit) {
    test::check_refused_options("evaluate", options, pointer, bound, unit);
}

// Fast: a narrow search around the default's critical speed, a short window.
const json fast_options = {
    {"critical_speed", {{"speed_min_m_per_s", 15}, {"speed_max_m_per_s", 25}}},
    {"amplitude", {{"window_s", 0.2}}},
};

}  // namespace

TEST_CASE("evaluate options: the defaults are resolved and echoed") {
    api::FieldErrors errors;
    const PreparedAnalysis prepared =
        prepare_evaluation(core::Scenario{}, json::object(), "/options", errors);
    CHECK(errors.empty());
    CHECK(prepared.resolved_options == json{{"critical_speed",
                                             {{"speed_min_m_per_s", 1.0},
                                              {"speed_max_m_per_s", 60.0},
                                              {"speed_step_m_per_s", 0.5},
                                              {"relative_tolerance", 1e-4}}},
                                            {"amplitude",
                                             {{"window_s", 2.0},
                                              {"excitation_amplitude_MPa", 1.0},
                                              {"excitation_frequency_Hz", 0.0},
                                              {"relative_tolerance", 1e-6},
                                              {"time_series", false},
                                              {"time_series_points", 2000}}},
                                            {"detail", "full"}});
}

TEST_CASE("evaluate options: nested bounds are reported at their own pointers") {
    check_evaluate_rejected({{"critical_speed", {{"speed_min_m_per_s", 0}}}},
                            "/options/critical_speed/speed_min_m_per_s", "[0.01, 100]", "m/s");
    check_evaluate_rejected({{"critical_speed", {{"speed_step_m_per_s", 1}}}},
                            "/options/critical_speed/speed_step_m_per_s", "(0, 0.5]", "m/s");
    check_evaluate_rejected({{"amplitude", {{"window_s", 30}}}}, "/options/amplitude/window_s",
                            "(0, 20]", "s");
    check_evaluate_rejected({{"amplitude", {{"excitation_amplitude_MPa", 500}}}},
                            "/options/amplitude/excitation_amplitude_MPa", "[0, 100]", "MPa");
    // evaluate runs at the scenario's speed: no speed list.
    check_evaluate_rejected({{"amplitude", {{"speeds_m_per_s", {10}}}}},
                            "/options/amplitude/speeds_m_per_s", std::nullopt, std::nullopt);
    check_evaluate_rejected({{"critical_speed", true}}, "/options/critical_speed", std::nullopt,
                            std::nullopt);
    check_evaluate_rejected({{"stability", json::object()}}, "/options/stability", std::nullopt,
                            std::nullopt);
}

TEST_CASE(
    "evaluate on the default scenario: roll gap, stable at 19 m/s, critical speed above, finite amplitude") {
    const Outcome outcome = evaluate({{"analysis", "evaluate"}, {"options", fast_options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    const json& result = outcome.body["result"];

    // The roll gap is the roll_gap analysis's own result.
    const Outcome roll_gap = evaluate({{"analysis", "roll_gap"}});
    REQUIRE(roll_gap.ok());
    CHECK(result["roll_gap"] == roll_gap.body["result"]);

    const json& stability = result["stability"];
    CHECK(stability["status"] == "ok");
    CHECK(stability["stable"] == true);
    CHECK(stability["least_damped_mode"]["frequency_Hz"].get<double>() > 80.0);
    CHECK(stability["least_damped_mode"]["frequency_Hz"].get<double>() < 130.0);

    const json& critical = result["critical_speed"];
    REQUIRE(critical["status"] == "found");
    CHECK(critical["critical_speed_m_per_s"].get<double>() > 19.0);  // stable at 19 m/s
    CHECK(critical["critical_speed_m_per_s"].get<double>() < 25.0);
    CHECK(critical["unstable_mode_frequency_Hz"].get<double>() > 80.0);

    const json& amplitude = result["amplitude"];
    CHECK(amplitude["speed_m_per_s"] == 19.0);
    CHECK(amplitude["upper_roll_amplitude_um"].get<double>() > 0.0);
    CHECK(std::isfinite(amplitude["upper_roll_amplitude_um"].get<double>()));
    CHECK(amplitude["excitation_frequency_Hz"] == stability["least_damped_mode"]["frequency_Hz"]);
    CHECK(amplitude["windows"].size() == 10);
}

TEST_CASE(
    "evaluate without a steady bite: a 200 result, the dynamics at that speed marked no_steady_state") {
    const Outcome outcome = evaluate(
        {{"analysis", "evaluate"},
         {"scenario",
          {{"lubricant", {{"limiting_shear", false}}}, {"rolls", {{"speed_m_per_s", 60}}}}},
         {"options", fast_options}});
    REQUIRE(outcome.ok());
    const json& result = outcome.body["result"];
    CHECK(result["roll_gap"]["status"] == "skidding");
    CHECK(result["stability"]["status"] == "no_steady_state");
    CHECK(result["stability"]["steady_status"] == "skidding");
    CHECK(result["stability"]["stable"].is_null());
    // the chatter limit is a search over speed: it is still answered, the same as the stability
    // analysis's
    const Outcome search = evaluate(
        {{"analysis", "stability"},
         {"scenario",
          {{"lubricant", {{"limiting_shear", false}}}, {"rolls", {{"speed_m_per_s", 60}}}}},
         {"options", fast_options["critical_speed"]}});
    REQUIRE(search.ok());
    CHECK(result["critical_speed"]["status"] == search.body["result"]["critical_speed"]["status"]);
    CHECK(result["critical_speed"]["critical_speed_m_per_s"] ==
          search.body["result"]["critical_speed"]["critical_speed_m_per_s"]);
    CHECK(result["amplitude"]["status"] == "no_steady_state");
    CHECK(result["amplitude"]["speed_m_per_s"] == 60.0);
    CHECK(result["amplitude"]["upper_roll_amplitude_um"].is_null());
}

TEST_CASE("the facade's Control: cancellation is the problem 'cancelled' (409)") {
    SUBCASE("already cancelled: nothing is computed") {
        int polls = 0;
        core::Control control;
        control.cancelled = [&polls] { return ++polls > 0; };
        const Outcome outcome =
            evaluate({{"analysis", "evaluate"}, {"options", fast_options}}, control);
        CHECK(outcome.problem == api::ProblemCode::cancelled);
        CHECK(outcome.http_status == 409);
        CHECK(outcome.media_type() == "application/problem+json");
        CHECK(outcome.body["type"] == "https://rollgap.dev/problems/cancelled");
        CHECK(polls == 1);
    }
    SUBCASE("cancelled while the critical speed is searched") {
        std::atomic<int> polls{0};
        core::Control control;
        control.cancelled = [&polls] { return ++polls > 5; };
        const Outcome outcome = evaluate(
            {{"analysis", "stability"}, {"options", fast_options["critical_speed"]}}, control);
        CHECK(outcome.problem == api::ProblemCode::cancelled);
    }
    SUBCASE("cancelled during a time integration, through evaluate_text") {
        std::atomic<int> polls{0};
        core::Control control;
        control.cancelled = [&polls] { return ++polls > 50; };
        const Outcome outcome =
            evaluate_text(R"({"analysis": "amplitude", "options": {"window_s": 0.2}})", control);
        CHECK(outcome.problem == api::ProblemCode::cancelled);
    }
    SUBCASE("cancelled during a tension cycle") {
        // core polls at the requested phases only, all in the last cycle: stop at the first.
        std::atomic<int> polls{0};
        core::Control control;
        control.cancelled = [&polls] { return ++polls > 1; };
        CHECK(evaluate({{"analysis", "tension_cycle"}}, control).problem ==
              api::ProblemCode::cancelled);
    }
    SUBCASE("an invalid request is reported as such, whatever the Control says") {
        core::Control control;
        control.cancelled = [] { return true; };
        CHECK(evaluate({{"analysis", "evaluate"}, {"options", {{"x", 1}}}}, control).problem ==
              api::ProblemCode::invalid_options);
    }
}

TEST_CASE("the facade's Control: progress is reported between 0 and 1") {
    std::mutex mutex;
    std::vector<double> reported;
    core::Control control;
    control.progress = [&](double fraction) {
        const std::lock_guard lock(mutex);
        reported.push_back(fraction);
    };
    const Outcome outcome =
        evaluate({{"analysis", "evaluate"}, {"options", fast_options}}, control);
    REQUIRE(outcome.ok());
    REQUIRE_FALSE(reported.empty());
    for (const double fraction : reported) {
        CHECK(fraction >= 0.0);
        CHECK(fraction <= 1.0);
    }
    CHECK(*std::max_element(reported.begin(), reported.end()) == rollgap::test::approx(1.0));
    // The same request without a Control gives the same document.
    CHECK(evaluate({{"analysis", "evaluate"}, {"options", fast_options}}).body == outcome.body);
}

TEST_CASE("cli: the new analyses run from the command line and are listed by --help") {
    std::istringstream in(R"({"analysis": "stability", "options": {"critical_speed": false}})");
    std::ostringstream out, err;
    const std::vector<std::string_view> arguments{"run", "-"};
    CHECK(run_cli(arguments, in, out, err) == exit_success);
    CHECK(json::parse(out.str())["result"]["stable"] == true);

    std::istringstream no_input;
    std::ostringstream help, help_err;
    const std::vector<std::string_view> help_arguments{"--help"};
    CHECK(run_cli(help_arguments, no_input, help, help_err) == exit_success);
    for (const char* name :
         {"roll_gap", "tension_cycle", "stability", "amplitude", "sweep", "evaluate"}) {
        CHECK(help.str().find(std::string("  ") + name + " ") != std::string::npos);
    }
}
