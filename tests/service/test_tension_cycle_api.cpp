// The analysis "tension_cycle" through the facade: options (cycles, phases; strict, bounded,
// echoed), the scenario rules of a sinusoidal back tension, and the distributions per phase.

#include <doctest/doctest.h>

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"
#include "service/analyses/tension_cycle.h"
#include "support/refused_options.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

Outcome run_tension_cycle(const json& options, const json& scenario = json::object()) {
    return evaluate({{"analysis", "tension_cycle"}, {"scenario", scenario}, {"options", options}});
}

void check_tension_cycle_rejected(const json& options, const std::string& pointer,
                                  std::optional<std::string> bound, std::optional<std::string> unit,
                                  const json& scenario = json::object()) {
    test::check_refused_options("tension_cycle", options, pointer, bound, unit, scenario);
}

}  // namespace

TEST_CASE(
    "tension_cycle options: the defaults are resolved and echoed, phases in the order they run") {
    api::FieldErrors errors;
    const PreparedAnalysis defaults =
        prepare_tension_cycle(core::Scenario{}, json::object(), "/options", errors);
    CHECK(errors.empty());
    CHECK(defaults.resolved_options ==
          json{{"cycles", 2}, {"phases", {0.25, 0.5, 0.75}}, {"relative_tolerance", 1e-6}});
    const PreparedAnalysis unsorted = prepare_tension_cycle(
        core::Scenario{}, {{"phases", {0.75, 0.0, 0.25}}}, "/options", errors);
    CHECK(errors.empty());
    CHECK(unsorted.resolved_options["phases"] == json{0.0, 0.25, 0.75});
}

TEST_CASE("tension_cycle options: every bound is enforced, with its pointer, bound and unit") {
    check_tension_cycle_rejected({{"cycles", 0}}, "/options/cycles", "[1, 20]", "1");
    check_tension_cycle_rejected({{"cycles", 21}}, "/options/cycles", "[1, 20]", "1");
    check_tension_cycle_rejected({{"cycles", 1.5}}, "/options/cycles", "[1, 20]", "1");
    check_tension_cycle_rejected({{"relative_tolerance", 0}}, "/options/relative_tolerance",
                                 "[1e-09, 0.001]", "1");
    check_tension_cycle_rejected({{"phases", 0.5}}, "/options/phases", std::nullopt, std::nullopt);
    check_tension_cycle_rejected({{"phases", json::array()}}, "/options/phases", "1 to 32 phases",
                                 std::nullopt);
    check_tension_cycle_rejected({{"phases", json(std::vector<double>(33, 0.5))}},
                                 "/options/phases", "1 to 32 phases", std::nullopt);
    check_tension_cycle_rejected({{"phases", {0.5, 1.0}}}, "/options/phases/1", "[0, 1)", "1");
    check_tension_cycle_rejected({{"phases", {-0.1}}}, "/options/phases/0", "[0, 1)", "1");
    check_tension_cycle_rejected({{"phases", {0.5, 0.25, 0.5}}}, "/options/phases/2", std::nullopt,
                                 "1");
    check_tension_cycle_rejected({{"phase", {0.5}}}, "/options/phase", std::nullopt, std::nullopt);
}

TEST_CASE("tension_cycle: the simulated time (cycles / frequency) is bounded") {
    // 3 cycles at 1 mHz would be 3000 s: at most 2 fit in 2000 s.
    check_tension_cycle_rejected({{"cycles", 3}}, "/options/cycles", "[1, 2]", "1",
                                 {{"tension", {{"back", {{"frequency_Hz", 0.001}}}}}});
}

TEST_CASE(
    "tension_cycle: the back tension runs as a sinusoid, so its limits apply whatever the mode") {
    // The default mode is "span"; 18 ± 20 MPa would go slack when run as a sinusoid.
    const Outcome outcome =
        run_tension_cycle(json::object(), {{"tension", {{"back", {{"amplitude_MPa", 20}}}}}});
    REQUIRE_FALSE(outcome.ok());
    CHECK(outcome.problem == api::ProblemCode::invalid_scenario);
    const json error = test::error_at(outcome, "/scenario/tension/back/amplitude_MPa");
    REQUIRE(error.is_object());
    CHECK(error["bound"] == "[0, 18]");
    CHECK(error["detail"].get<std::string>().find("tension_cycle") != std::string::npos);
    // The roll_gap analysis does not run the sinusoid: the same scenario is fine there.
    CHECK(evaluate({{"analysis", "roll_gap"},
                    {"scenario", {{"tension", {{"back", {{"amplitude_MPa", 20}}}}}}},
                    {"options", {{"distributions", false}}}})
              .ok());
}

TEST_CASE(
    "tension_cycle on the default scenario: s_b = mean + amplitude sin(2 pi T), distributions per phase") {
    const Outcome outcome = run_tension_cycle(json::object());
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    const json& result = outcome.body["result"];
    CHECK(result["status"] == "ok");
    CHECK(result["steady_status"] == "ok");
    CHECK(result["frequency_Hz"] == 10.0);
    const json& phases = result["phases"];
    REQUIRE(phases.size() == 3);
    // Mean 18 MPa, amplitude 9 MPa (docs/model.md §6).
    CHECK(phases[0]["phase"] == 0.25);
    CHECK(phases[0]["back_tension_MPa"].get<double>() == rollgap::test::approx(27.0).epsilon(1e-9));
    CHECK(phases[1]["back_tension_MPa"].get<double>() == rollgap::test::approx(18.0).epsilon(1e-9));
    CHECK(phases[2]["back_tension_MPa"].get<double>() == rollgap::test::approx(9.0).epsilon(1e-9));
    // In the last of the 2 cycles of 0.1 s.
    CHECK(phases[0]["time_s"].get<double>() == rollgap::test::approx(0.125));
    CHECK(phases[2]["time_s"].get<double>() == rollgap::test::approx(0.175));

    // Each phase carries the roll_gap analysis's own result document, with distributions.
    const Outcome roll_gap = evaluate({{"analysis", "roll_gap"}});
    REQUIRE(roll_gap.ok());
    for (const json& phase : phases) {
        CAPTURE(phase["phase"].get<double>());
        const json& bite = phase["roll_gap"];
        CHECK(bite["status"] == "ok");
        for (const auto& member : roll_gap.body["result"].items())
            CHECK(bite.contains(member.key()));
        CHECK(bite["distribution"]["x_mm"].size() ==
              roll_gap.body["result"]["distribution"]["x_mm"].size());
        CHECK(phase["inlet_film_um"].get<double>() > 0.0);
        CHECK(phase["gap_um"].is_number());
    }
    // More back tension, less roll force (the entry pressure is sigma - s_b).
    CHECK(phases[0]["roll_gap"]["force_kN"].get<double>() <
          phases[2]["roll_gap"]["force_kN"].get<double>());
}
