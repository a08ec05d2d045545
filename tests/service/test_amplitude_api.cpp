// The analysis "amplitude" through the facade: options (speeds, window, excitation, time
// series; strict, bounded, echoed) and the per-speed result of the nonlinear time integration.

#include <doctest/doctest.h>

#include <cmath>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "service/analyses/amplitude.h"
#include "service/evaluate.h"
#include "support/refused_options.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

void check_amplitude_rejected(const json& options, const std::string& pointer,
                              std::optional<std::string> bound, std::optional<std::string> unit) {
    test::check_refused_options("amplitude", options, pointer, bound, unit);
}

json run_amplitude(const json& options, const json& scenario = json::object()) {
    const Outcome outcome =
        evaluate({{"analysis", "amplitude"}, {"scenario", scenario}, {"options", options}});
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    return outcome.body;
}

bool positive_finite(const json& value) {
    return value.is_number() && std::isfinite(value.get<double>()) && value.get<double>() > 0.0;
}

}  // namespace

TEST_CASE("amplitude options: the defaults are resolved and echoed, the speed is the scenario's") {
    core::Scenario scenario;
    scenario.rolls.speed = 12.0;
    api::FieldErrors errors;
    const PreparedAnalysis prepared =
        prepare_amplitude(scenario, json::object(), "/options", errors);
    CHECK(errors.empty());
    CHECK(prepared.resolved_options == json{{"speeds_m_per_s", {12.0}},
                                            {"window_s", 2.0},
                                            {"excitation_amplitude_MPa", 1.0},
                                            {"excitation_frequency_Hz", 0.0},
                                            {"relative_tolerance", 1e-6},
                                            {"time_series", false},
                                            {"time_series_points", 2000}});
}

TEST_CASE("amplitude options: every bound is enforced, with its pointer, bound and unit") {
    check_amplitude_rejected({{"window_s", 0}}, "/options/window_s", "(0, 20]", "s");
    check_amplitude_rejected({{"window_s", 20.5}}, "/options/window_s", "(0, 20]", "s");
    check_amplitude_rejected({{"excitation_amplitude_MPa", -1}},
                             "/options/excitation_amplitude_MPa", "[0, 100]", "MPa");
    check_amplitude_rejected({{"excitation_amplitude_MPa", 101}},
                             "/options/excitation_amplitude_MPa", "[0, 100]", "MPa");
    check_amplitude_rejected({{"excitation_frequency_Hz", -1}}, "/options/excitation_frequency_Hz",
                             "[0, 2000]", "Hz");
    check_amplitude_rejected({{"excitation_frequency_Hz", 2001}},
                             "/options/excitation_frequency_Hz", "[0, 2000]", "Hz");
    check_amplitude_rejected({{"relative_tolerance", 1e-12}}, "/options/relative_tolerance",
                             "[1e-09, 0.001]", "1");
    check_amplitude_rejected({{"relative_tolerance", 0.01}}, "/options/relative_tolerance",
                             "[1e-09, 0.001]", "1");
    check_amplitude_rejected({{"time_series", 1}}, "/options/time_series", std::nullopt,
                             std::nullopt);
    check_amplitude_rejected({{"time_series_points", 1}}, "/options/time_series_points",
                             "[2, 20000]", "1");
    check_amplitude_rejected({{"time_series_points", 20001}}, "/options/time_series_points",
                             "[2, 20000]", "1");
    check_amplitude_rejected({{"time_series_points", 10.5}}, "/options/time_series_points",
                             "[2, 20000]", "1");
    check_amplitude_rejected({{"window", 1}}, "/options/window", std::nullopt, std::nullopt);
}

TEST_CASE("amplitude options: speeds are 1 to 64 scenario speeds") {
    check_amplitude_rejected({{"speeds_m_per_s", 19}}, "/options/speeds_m_per_s", std::nullopt,
                             std::nullopt);
    check_amplitude_rejected({{"speeds_m_per_s", json::array()}}, "/options/speeds_m_per_s",
                             "1 to 64 speeds", std::nullopt);
    check_amplitude_rejected({{"speeds_m_per_s", json(std::vector<double>(65, 10.0))}},
                             "/options/speeds_m_per_s", "1 to 64 speeds", std::nullopt);
    // Each speed has the bounds of /scenario/rolls/speed_m_per_s.
    check_amplitude_rejected({{"speeds_m_per_s", {10, 200}}}, "/options/speeds_m_per_s/1",
                             "[0.01, 100]", "m/s");
    check_amplitude_rejected({{"speeds_m_per_s", {10, "fast"}}}, "/options/speeds_m_per_s/1",
                             std::nullopt, std::nullopt);
}

TEST_CASE(
    "amplitude at the scenario's speed: a positive, finite response at the least-damped frequency") {
    const json body = run_amplitude({{"window_s", 0.2}});
    REQUIRE(body["result"]["points"].size() == 1);
    const json& point = body["result"]["points"][0];
    CHECK(point["speed_m_per_s"] == 19.0);
    CHECK(std::set<std::string>{"settled", "growing", "decaying"}.count(
              point["status"].get<std::string>()) == 1);
    CHECK(point["steady_status"] == "ok");
    CHECK(point["end_status"] == "ok");
    CHECK(point["end_time_s"].get<double>() == rollgap::test::approx(0.2));
    // Excited at the least-damped eigenfrequency (~104 Hz), stable at 19 m/s.
    CHECK(point["excitation_frequency_Hz"].get<double>() > 80.0);
    CHECK(point["excitation_frequency_Hz"].get<double>() < 130.0);
    CHECK(point["least_damped_growth_rate_per_s"].get<double>() < 0.0);
    CHECK(positive_finite(point["upper_roll_amplitude_um"]));
    CHECK(positive_finite(point["gap_amplitude_um"]));
    CHECK(positive_finite(point["force_amplitude_kN"]));
    // The stack is symmetric: the work rolls move apart, the gap swings about twice as far.
    CHECK(point["gap_amplitude_um"].get<double>() > point["upper_roll_amplitude_um"].get<double>());
    CHECK(point["settled"].is_boolean());
    CHECK(point["growth_rate_per_s"].is_number());
    REQUIRE(point["windows"].size() == 10);
    CHECK(point["windows"][9]["end_s"].get<double>() == rollgap::test::approx(0.2));
    CHECK(point["windows"][9]["upper_roll_amplitude_um"] == point["upper_roll_amplitude_um"]);
    CHECK_FALSE(point.contains("time_series"));
}

TEST_CASE(
    "amplitude at several speeds: one point per speed, in order, the amplitude rises with speed") {
    const json body = run_amplitude({{"speeds_m_per_s", {15, 10}}, {"window_s", 0.2}});
    CHECK(body["options"]["speeds_m_per_s"] == json{15.0, 10.0});
    const json& points = body["result"]["points"];
    REQUIRE(points.size() == 2);
    CHECK(points[0]["speed_m_per_s"] == 15.0);
    CHECK(points[1]["speed_m_per_s"] == 10.0);
    // Fig. 13 of the paper: closer to the critical speed, the response is larger.
    CHECK(points[0]["upper_roll_amplitude_um"].get<double>() >
          points[1]["upper_roll_amplitude_um"].get<double>());
    // The same speed alone gives the same figures (parallel runs are independent).
    const json alone = run_amplitude({{"speeds_m_per_s", {10}}, {"window_s", 0.2}});
    CHECK(alone["result"]["points"][0] == points[1]);
}

TEST_CASE("amplitude: the time series, decimated, when asked for") {
    const json body =
        run_amplitude({{"window_s", 0.2}, {"time_series", true}, {"time_series_points", 100}});
    const json& series = body["result"]["points"][0]["time_series"];
    const std::size_t n = series["time_s"].size();
    // core decimates with a whole-number stride, floor(samples / points), so it returns between
    // points and 2 × points samples (reported: "at most points" is its contract).
    CHECK(n >= 100);
    CHECK(n < 200);
    for (const char* column :
         {"upper_work_roll_displacement_um", "work_roll_gap_change_um", "roll_force_change_kN"}) {
        CHECK(series[column].size() == n);
    }
    for (std::size_t i = 1; i < n; ++i)
        CHECK(series["time_s"][i].get<double>() > series["time_s"][i - 1].get<double>());
    CHECK(series["time_s"][n - 1].get<double>() <= 0.2);
}

TEST_CASE("amplitude: a physical limit or no steady state is a 200 result with a status") {
    SUBCASE("above the critical speed the response grows until a limit or the end of the window") {
        const json point =
            run_amplitude({{"speeds_m_per_s", {22}}, {"window_s", 0.5}})["result"]["points"][0];
        const std::string status = point["status"];
        CHECK((status == "limit_reached" || status == "growing"));
        CHECK(point["least_damped_growth_rate_per_s"].get<double>() > 0.0);
        if (status == "limit_reached") {
            CHECK(std::set<std::string>{"contact_lost", "skidding", "slack_strip"}.count(
                      point["end_status"].get<std::string>()) == 1);
            CHECK(point["end_time_s"].get<double>() < 0.5);
        } else {
            CHECK(point["growth_rate_per_s"].get<double>() > 0.0);
        }
    }
    SUBCASE("no steady state") {
        const json point = run_amplitude(
            {{"window_s", 0.2}}, {{"lubricant", {{"limiting_shear", false}}},
                                  {"rolls", {{"speed_m_per_s", 60}}}})["result"]["points"][0];
        CHECK(point["status"] == "no_steady_state");
        CHECK(point["steady_status"] == "skidding");
        CHECK(point["upper_roll_amplitude_um"].is_null());
        CHECK(point["end_status"].is_null());
        CHECK(point["windows"].empty());
    }
}
