// The analysis "sweep" through the facade: the parameter (a numeric scenario field), the values
// (each validated as that field of the scenario), the work bounds, the results, and their
// independence of the thread count.

#include <doctest/doctest.h>

#include <array>
#include <atomic>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"
#include "service/analyses/sweep.h"
#include "support/pool_control.h"
#include "support/refused_options.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

Outcome run_sweep(const json& options, const json& scenario = json::object()) {
    return evaluate({{"analysis", "sweep"}, {"scenario", scenario}, {"options", options}});
}

json rejected(const json& options, const std::string& pointer,
              const json& scenario = json::object()) {
    return test::refused_options("sweep", options, pointer, scenario);
}

bool mentions(const json& error, const std::string& text) {
    return error["detail"].get<std::string>().find(text) != std::string::npos;
}

const json viscosity_values = {{"parameter", "/lubricant/viscosity_Pa_s"},
                               {"values", {3e-4, 8e-4}}};

// A fast critical-speed search around the default's critical speed (~20 m/s).
const json narrow_search = {
    {"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 35}, {"speed_step_m_per_s", 0.5}};

}  // namespace

TEST_CASE("sweep options: the defaults are resolved and echoed") {
    api::FieldErrors errors;
    const PreparedAnalysis prepared =
        prepare_sweep(core::Scenario{}, viscosity_values, "/options", errors);
    CHECK(errors.empty());
    CHECK(prepared.resolved_options == json{{"parameter", "/lubricant/viscosity_Pa_s"},
                                            {"values", {3e-4, 8e-4}},
                                            {"quantity", "critical_speed"},
                                            {"critical_speed",
                                             {{"speed_min_m_per_s", 1.0},
                                              {"speed_max_m_per_s", 60.0},
                                              {"speed_step_m_per_s", 0.5},
                                              {"relative_tolerance", 1e-4}}}});
    const PreparedAnalysis amplitude =
        prepare_sweep(core::Scenario{},
                      {{"parameter", "/rolls/speed_m_per_s"},
                       {"range", {{"from", 5}, {"to", 15}, {"count", 3}}},
                       {"quantity", "amplitude"}},
                      "/options", errors);
    CHECK(errors.empty());
    CHECK(amplitude.resolved_options == json{{"parameter", "/rolls/speed_m_per_s"},
                                             {"range", {{"from", 5.0}, {"to", 15.0}, {"count", 3}}},
                                             {"quantity", "amplitude"},
                                             {"amplitude",
                                              {{"window_s", 2.0},
                                               {"excitation_amplitude_MPa", 1.0},
                                               {"excitation_frequency_Hz", 0.0},
                                               {"relative_tolerance", 1e-6}}}});
}

TEST_CASE("sweep options: the parameter must name a numeric field of the scenario") {
    CHECK(mentions(rejected({{"values", {1}}}, "/options/parameter"), "required"));
    const json unknown = rejected({{"parameter", "/lubricant/viscosity_Pa"}, {"values", {1e-3}}},
                                  "/options/parameter");
    CHECK(mentions(unknown, "did you mean '/lubricant/viscosity_Pa_s'"));
    CHECK(unknown["bound"].get<std::string>().find("/rolls/radius_mm") != std::string::npos);
    CHECK(mentions(rejected({{"parameter", "lubricant/viscosity_Pa_s"}, {"values", {1e-3}}},
                            "/options/parameter"),
                   "did you mean '/lubricant/viscosity_Pa_s'"));
    CHECK(
        mentions(rejected({{"parameter", "/scenario/lubricant/viscosity_Pa_s"}, {"values", {1e-3}}},
                          "/options/parameter"),
                 "did you mean '/lubricant/viscosity_Pa_s'"));
    CHECK(mentions(
        rejected({{"parameter", "/friction/model"}, {"values", {1}}}, "/options/parameter"),
        "choice field"));
    CHECK(mentions(rejected({{"parameter", "/lubricant/limiting_shear"}, {"values", {1}}},
                            "/options/parameter"),
                   "boolean field"));
    CHECK(mentions(rejected({{"parameter", "/strip"}, {"values", {1}}}, "/options/parameter"),
                   "group"));
    CHECK(mentions(rejected({{"parameter", 7}, {"values", {1}}}, "/options/parameter"),
                   "must be a string"));
    // The critical-speed search scans the speed itself.
    CHECK(mentions(
        rejected({{"parameter", "/rolls/speed_m_per_s"}, {"values", {10}}}, "/options/parameter"),
        "scans the roll speed"));
}

TEST_CASE("sweep options: exactly one of values and range, within the point limit") {
    const json parameter = {{"parameter", "/rolls/radius_mm"}};
    const auto with = [&parameter](const json& extra) {
        json options = parameter;
        options.update(extra);
        return options;
    };
    CHECK(mentions(rejected(parameter, "/options/values"), "required"));
    CHECK(mentions(
        rejected(with({{"values", {200}}, {"range", {{"from", 200}, {"to", 300}, {"count", 2}}}}),
                 "/options/range"),
        "not both"));
    CHECK(rejected(with({{"values", json::array()}}), "/options/values")["bound"] ==
          "1 to 1000 values");
    CHECK(rejected(with({{"values", json(std::vector<double>(1001, 200.0))}}),
                   "/options/values")["bound"] == "1 to 1000 values");
    CHECK(rejected(with({{"values", 200}}), "/options/values").is_object());
    CHECK(rejected(with({{"range", {{"from", 200}, {"to", 300}, {"count", 1}}}}),
                   "/options/range/count")["bound"] == "[2, 1000]");
    CHECK(rejected(with({{"range", {{"from", 200}, {"to", 300}, {"count", 1001}}}}),
                   "/options/range/count")["bound"] == "[2, 1000]");
    CHECK(mentions(rejected(with({{"range", {{"from", 200}, {"count", 3}}}}), "/options/range/to"),
                   "required"));
    CHECK(
        mentions(rejected(with({{"range", {{"from", 200}, {"to", 300}}}}), "/options/range/count"),
                 "required"));
    CHECK(rejected(with({{"range", {{"from", 200}, {"to", 300}, {"count", 3}, {"step", 1}}}}),
                   "/options/range/step")
              .is_object());
    CHECK(rejected(with({{"range", {{"from", "a"}, {"to", 300}, {"count", 3}}}}),
                   "/options/range/from")
              .is_object());
    CHECK(rejected(with({{"range", 3}}), "/options/range").is_object());
}

TEST_CASE("sweep values are validated as the field they set, with its bound and unit") {
    // /lubricant/viscosity_Pa_s is bounded to [1e-5, 10] Pa.s.
    const json out_of_bounds =
        rejected({{"parameter", "/lubricant/viscosity_Pa_s"}, {"values", {1e-4, 5e-4, 1e-3, 20}}},
                 "/options/values/3");
    CHECK(out_of_bounds["bound"] == "[0.00001, 10]");
    CHECK(out_of_bounds["unit"] == "Pa.s");
    CHECK(mentions(out_of_bounds, "20 Pa.s is outside"));
    CHECK(
        mentions(rejected({{"parameter", "/lubricant/viscosity_Pa_s"}, {"values", {1e-4, "thick"}}},
                          "/options/values/1"),
                 "must be a number"));
    // The ends of a range, and a point in between.
    const json from = rejected(
        {{"parameter", "/rolls/radius_mm"}, {"range", {{"from", 5}, {"to", 300}, {"count", 3}}}},
        "/options/range/from");
    CHECK(from["bound"] == "[10, 2000]");
    CHECK(from["unit"] == "mm");
    CHECK(rejected({{"parameter", "/rolls/radius_mm"},
                    {"range", {{"from", 300}, {"to", 3000}, {"count", 3}}}},
                   "/options/range/to")["bound"] == "[10, 2000]");
    // Integer fields: bite_intervals must be even.
    CHECK(rejected({{"parameter", "/numerics/bite_intervals"}, {"values", {32, 33}}},
                   "/options/values/1")["bound"] == "[8, 4096], even");
    // A value fine for its field but not with the rest of the scenario (the back tension of
    // 18 MPa must stay below the flow stress): reported at the value, naming the other field.
    const json cross = rejected({{"parameter", "/strip/flow_stress_MPa"}, {"values", {380, 15}}},
                                "/options/values/1");
    CHECK(mentions(cross, "/scenario/tension/back/stress_MPa"));
    const json interior = rejected({{"parameter", "/strip/flow_stress_MPa"},
                                    {"range", {{"from", 380}, {"to", 10}, {"count", 100}}}},
                                   "/options/range/to");
    CHECK(interior.is_object());
    // ... and the first point inside the range that fails (17.47 MPa), at the range itself.
    CHECK(mentions(rejected({{"parameter", "/strip/flow_stress_MPa"},
                             {"range", {{"from", 380}, {"to", 10}, {"count", 100}}}},
                            "/options/range"),
                   "point 97 of the range"));
    // The values are checked against the request's own scenario: with a flow stress of 100 MPa
    // a back tension of 150 MPa is out.
    CHECK(rejected({{"parameter", "/tension/back/stress_MPa"}, {"values", {50, 150}}},
                   "/options/values/1", {{"strip", {{"flow_stress_MPa", 100}}}})
              .is_object());
}

TEST_CASE("sweep options: the quantity and its own options") {
    const json quantity =
        rejected({{"parameter", "/rolls/radius_mm"}, {"values", {200}}, {"quantity", "force"}},
                 "/options/quantity");
    CHECK(quantity["bound"] == "critical_speed | amplitude");
    CHECK(mentions(
        rejected(
            {{"parameter", "/rolls/radius_mm"}, {"values", {200}}, {"amplitude", json::object()}},
            "/options/amplitude"),
        "applies to quantity 'amplitude' only"));
    CHECK(mentions(rejected({{"parameter", "/rolls/radius_mm"},
                             {"values", {200}},
                             {"quantity", "amplitude"},
                             {"critical_speed", json::object()}},
                            "/options/critical_speed"),
                   "applies to quantity 'critical_speed' only"));
    CHECK(rejected({{"parameter", "/rolls/radius_mm"},
                    {"values", {200}},
                    {"critical_speed", {{"speed_step_m_per_s", 0.6}}}},
                   "/options/critical_speed/speed_step_m_per_s")["bound"] == "(0, 0.5]");
    CHECK(rejected({{"parameter", "/rolls/radius_mm"},
                    {"values", {200}},
                    {"quantity", "amplitude"},
                    {"amplitude", {{"window_s", 0}}}},
                   "/options/amplitude/window_s")["bound"] == "(0, 20]");
    // A sweep reports figures per value, not time series.
    CHECK(rejected({{"parameter", "/rolls/radius_mm"},
                    {"values", {200}},
                    {"quantity", "amplitude"},
                    {"amplitude", {{"time_series", true}}}},
                   "/options/amplitude/time_series")
              .is_object());
}

TEST_CASE("sweep options: the total work is bounded") {
    // 1000 values × 2.5 s = 2500 s of simulated time > 2000 s: at most 2 s per value.
    const json simulated = rejected({{"parameter", "/rolls/speed_m_per_s"},
                                     {"range", {{"from", 1}, {"to", 50}, {"count", 1000}}},
                                     {"quantity", "amplitude"},
                                     {"amplitude", {{"window_s", 2.5}}}},
                                    "/options/amplitude/window_s");
    CHECK(simulated["bound"] == "(0, 2]");
    CHECK(simulated["unit"] == "s");
    // 1000 × 2 s (the default window) fits exactly.
    api::FieldErrors errors;
    prepare_sweep(core::Scenario{},
                  {{"parameter", "/rolls/speed_m_per_s"},
                   {"range", {{"from", 1}, {"to", 50}, {"count", 1000}}},
                   {"quantity", "amplitude"}},
                  "/options", errors);
    CHECK(errors.empty());
    // 1000 values × 591 scan speeds > 250000 stability evaluations.
    CHECK(mentions(rejected({{"parameter", "/rolls/radius_mm"},
                             {"range", {{"from", 100}, {"to", 500}, {"count", 1000}}},
                             {"critical_speed", {{"speed_step_m_per_s", 0.1}}}},
                            "/options/critical_speed/speed_step_m_per_s"),
                   "250000"));
}

TEST_CASE(
    "sweep of the critical speed over the viscosity: the critical speed falls as it rises (Fig. 8)") {
    json options = viscosity_values;
    options["critical_speed"] = narrow_search;
    const Outcome outcome = run_sweep(options);
    REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
    const json& result = outcome.body["result"];
    CHECK(result["parameter"] == "/lubricant/viscosity_Pa_s");
    CHECK(result["unit"] == "Pa.s");
    CHECK(result["quantity"] == "critical_speed");
    const json& points = result["points"];
    REQUIRE(points.size() == 2);
    CHECK(result["value_name"] == "value_Pa_s");
    CHECK(points[0]["value_Pa_s"] == 3e-4);
    CHECK(points[1]["value_Pa_s"] == 8e-4);
    for (const json& point : points) {
        REQUIRE(point["status"] == "found");
        CHECK(point["critical_speed_m_per_s"].get<double>() > 10.0);
        CHECK(point["critical_speed_m_per_s"].get<double>() < 35.0);
        CHECK(point["frequency_Hz"].get<double>() > 50.0);
    }
    CHECK(points[1]["critical_speed_m_per_s"].get<double>() <
          points[0]["critical_speed_m_per_s"].get<double>());

    // A point equals the stability analysis of the same scenario.
    json search = narrow_search;
    const Outcome single = evaluate({{"analysis", "stability"},
                                     {"scenario", {{"lubricant", {{"viscosity_Pa_s", 8e-4}}}}},
                                     {"options", search}});
    REQUIRE(single.ok());
    CHECK(single.body["result"]["critical_speed"]["critical_speed_m_per_s"] ==
          points[1]["critical_speed_m_per_s"]);
}

TEST_CASE("sweep results are identical on 1 and 2 threads") {
    SUBCASE("critical speed") {
        const json request = {{"analysis", "sweep"},
                              {"options",
                               {{"parameter", "/roughness/strip_rq_um"},
                                {"values", {1.0, 1.6, 3.0}},
                                {"critical_speed", narrow_search}}}};
        const Outcome one = evaluate(request, test::PoolControl(1).control);
        const Outcome two = evaluate(request, test::PoolControl(2).control);
        REQUIRE(one.ok());
        CHECK(one.body == two.body);
        CHECK(one.body == evaluate(request).body);  // and with no pool at all
    }
    SUBCASE("amplitude") {
        const json request = {{"analysis", "sweep"},
                              {"options",
                               {{"parameter", "/rolls/speed_m_per_s"},
                                {"values", {8, 12, 16}},
                                {"quantity", "amplitude"},
                                {"amplitude", {{"window_s", 0.1}}}}}};
        const Outcome one = evaluate(request, test::PoolControl(1).control);
        const Outcome two = evaluate(request, test::PoolControl(2).control);
        REQUIRE(one.ok());
        CHECK(one.body == two.body);
        const json& points = one.body["result"]["points"];
        REQUIRE(points.size() == 3);
        for (const json& point : points)
            CHECK(point["upper_roll_amplitude_um"].get<double>() > 0.0);
        CHECK(points[0]["frequency_Hz"].get<double>() > 50.0);
    }
}

TEST_CASE("a cancelled sweep is the problem 'cancelled', not a result of unfinished points") {
    std::atomic<int> polls{0};
    core::Control control;
    control.cancelled = [&polls] { return ++polls > 3; };
    const Outcome outcome = evaluate({{"analysis", "sweep"},
                                      {"options",
                                       {{"parameter", "/rolls/radius_mm"},
                                        {"range", {{"from", 200}, {"to", 400}, {"count", 20}}},
                                        {"critical_speed", narrow_search}}}},
                                     control);
    REQUIRE_FALSE(outcome.ok());
    CHECK(outcome.problem == api::ProblemCode::cancelled);
    CHECK(outcome.http_status == 409);
}
