// Roll-bite result → JSON: units in the names, columnar distributions, statuses as values.

#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "api/result_json.h"

using nlohmann::json;
using namespace rollgap;

namespace {

core::BitePoint point(double x, double pressure, core::Regime regime) {
    return {x, pressure, -1e6, 2e-6, 1.0, 0.3, 18.0, 1.5e-3, regime};
}

}  // namespace

TEST_CASE("a solved bite is written in engineering units with columnar distributions") {
    core::BiteResult result;
    result.status = core::BiteStatus::ok;
    result.message = "ok";
    result.force = 6.5e6;
    result.torque = 3.3e4;
    result.neutral_point = 2.9e-3;
    result.contact_length = 8.2e-3;
    result.inlet_film = 3.4e-6;
    result.entry_speed = 16.5;
    result.forward_slip = 0.02;
    result.distribution = {point(0.0, 362e6, core::Regime::mixed),
                           point(1e-3, 400e6, core::Regime::boundary),
                           point(8.2e-3, 362e6, core::Regime::full_film)};
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "ok");
    CHECK(body["force_kN"] == 6500.0);
    CHECK(body["torque_kN_m"] == 33.0);
    CHECK(body["neutral_point_mm"] == 2.9);
    CHECK(body["contact_length_mm"] == 8.2);
    CHECK(body["inlet_film_um"] == 3.4);
    CHECK(body["entry_speed_m_per_s"] == 16.5);
    CHECK(body["forward_slip"] == 0.02);
    CHECK_FALSE(body.contains("skidding"));

    const json& distribution = body["distribution"];
    for (const char* column : {"x_mm", "pressure_MPa", "friction_MPa", "film_um", "film_ratio",
                               "contact_ratio", "strip_speed_m_per_s", "thickness_mm", "regime"}) {
        CAPTURE(column);
        REQUIRE(distribution.contains(column));
        CHECK(distribution[column].size() == 3);
    }
    CHECK(distribution["x_mm"] == json::array({0.0, 1.0, 8.2}));
    CHECK(distribution["pressure_MPa"] == json::array({362.0, 400.0, 362.0}));
    CHECK(distribution["friction_MPa"][0] == -1.0);
    CHECK(distribution["film_um"][0] == 2.0);
    CHECK(distribution["thickness_mm"][0] == 1.5);
    CHECK(distribution["regime"] == json::array({"mixed", "boundary", "full_film"}));
}

TEST_CASE("skidding is a result with its details, not an error") {
    core::BiteResult result;
    result.status = core::BiteStatus::skidding;
    result.message = "no neutral point";
    result.skid_at_exit = true;
    result.skid_residual = -2.5e6;
    result.contact_length = 8.2e-3;
    result.inlet_angle = 0.03;
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "skidding");
    CHECK(body["message"] == "no neutral point");
    CHECK(body["skidding"]["neutral_point_left_at"] == "exit");
    CHECK(body["skidding"]["residual_MPa"] == -2.5);
    CHECK_FALSE(body.contains("distribution"));
    // No steady state: no force, speeds or film, rather than core's placeholder zeros.
    for (const char* unsolved :
         {"force_kN", "torque_kN_m", "neutral_point_mm", "entry_speed_m_per_s",
          "exit_speed_m_per_s", "forward_slip", "inlet_film_um", "mean_friction_coefficient"}) {
        CAPTURE(unsolved);
        CHECK(body[unsolved].is_null());
    }
    CHECK(body["contact_length_mm"] == 8.2);
    CHECK(body["inlet_angle_rad"] == 0.03);
}

TEST_CASE("contact lost carries zero force and no solution") {
    core::BiteResult result;
    result.status = core::BiteStatus::contact_lost;
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "contact_lost");
    CHECK(body["force_kN"] == 0.0);
    CHECK(body["neutral_point_mm"].is_null());
    CHECK(body["contact_length_mm"].is_null());
}

TEST_CASE("non-finite values of a failed solve are written as null") {
    core::BiteResult result;
    result.status = core::BiteStatus::solver_failure;
    result.force = std::nan("");
    const json body = api::bite_result_json(result);
    CHECK(body["status"] == "solver_failure");
    CHECK(body["force_kN"].is_null());
    CHECK(body.dump().find("NaN") == std::string::npos);
}

// ---- the schemas the tables give (service/openapi.cpp) describe what the same tables write ----

#include <regex>

#include "service/evaluate.h"
#include "service/openapi.h"

namespace {

// The JSON Schema keywords the result schemas use, checked strictly: a member the schema does
// not list, a missing required one, a wrong type or enum value is reported with its pointer.
bool conforms(const json& value, const json& schema, const json& components, const std::string& at,
              std::string& why) {
    if (schema.contains("$ref")) {
        const std::string ref = schema["$ref"];
        return conforms(value, components.at(ref.substr(ref.rfind('/') + 1)), components, at, why);
    }
    if (schema.contains("oneOf")) {
        int matches = 0;
        std::string ignored;
        for (const json& option : schema["oneOf"])
            matches += conforms(value, option, components, at, ignored) ? 1 : 0;
        if (matches != 1) {
            why = at + ": matches " + std::to_string(matches) + " of oneOf";
            return false;
        }
    }
    if (schema.contains("enum") &&
        std::find(schema["enum"].begin(), schema["enum"].end(), value) == schema["enum"].end()) {
        why = at + ": " + value.dump() + " not in " + schema["enum"].dump();
        return false;
    }
    if (schema.contains("type")) {
        const json types =
            schema["type"].is_array() ? schema["type"] : json::array({schema["type"]});
        bool typed = false;
        for (const json& type : types) {
            typed = typed || (type == "null" && value.is_null()) ||
                    (type == "number" && value.is_number()) ||
                    (type == "integer" && value.is_number_integer()) ||
                    (type == "boolean" && value.is_boolean()) ||
                    (type == "string" && value.is_string()) ||
                    (type == "array" && value.is_array()) ||
                    (type == "object" && value.is_object());
        }
        if (!typed) {
            why = at + ": " + value.dump().substr(0, 80) + " is not " + types.dump();
            return false;
        }
    }
    if (value.is_array() && schema.contains("items")) {
        for (std::size_t i = 0; i < value.size(); ++i) {
            if (!conforms(value[i], schema["items"], components, at + "/" + std::to_string(i), why))
                return false;
        }
    }
    const json required = schema.value("required", json::array());
    for (const json& name : required) {
        if (value.is_object() && !value.contains(name.get<std::string>())) {
            why = at + ": lacks required " + name.get<std::string>();
            return false;
        }
    }
    if (value.is_object() && schema.contains("properties")) {
        const json patterns = schema.value("patternProperties", json::object());
        for (const auto& [name, member] : value.items()) {
            if (schema["properties"].contains(name)) {
                if (!conforms(member, schema["properties"][name], components, at + "/" + name, why))
                    return false;
                continue;
            }
            bool patterned = false;
            for (const auto& [pattern, sub] : patterns.items()) {
                if (std::regex_search(name, std::regex(pattern))) {
                    patterned = true;
                    if (!conforms(member, sub, components, at + "/" + name, why)) return false;
                }
            }
            if (!patterned && schema.value("additionalProperties", true) == false) {
                why = at + ": member " + name + " is not in the schema";
                return false;
            }
        }
    }
    return true;
}

}  // namespace

TEST_CASE("every analysis' result conforms to the schema its tables give, whatever the outcome") {
    const json document = service::openapi_document();
    const json& components = document["components"]["schemas"];
    const json skids = {{"lubricant", {{"limiting_shear", false}}},
                        {"rolls", {{"speed_m_per_s", 40}}}};
    const json narrow = {{"speed_min_m_per_s", 15}, {"speed_max_m_per_s", 25}};
    const json requests = json::array({
        {{"analysis", "roll_gap"}},
        {{"analysis", "roll_gap"}, {"scenario", skids}},
        {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}},
        {{"analysis", "stability"}, {"options", narrow}},
        {{"analysis", "stability"},
         {"options",
          {{"speed_min_m_per_s", 20.5}, {"speed_max_m_per_s", 22}, {"detail", "summary"}}}},
        {{"analysis", "stability"}, {"scenario", skids}, {"options", {{"critical_speed", false}}}},
        {{"analysis", "amplitude"},
         {"options", {{"window_s", 0.2}, {"time_series", true}, {"time_series_points", 10}}}},
        {{"analysis", "amplitude"}, {"scenario", skids}},
        {{"analysis", "tension_cycle"}, {"options", {{"phases", {0.5}}}}},
        {{"analysis", "tension_cycle"}, {"scenario", skids}},
        {{"analysis", "sweep"},
         {"options",
          {{"parameter", "/strip/reduction"}, {"values", {0.1, 0.2}}, {"critical_speed", narrow}}}},
        {{"analysis", "sweep"},
         {"options",
          {{"parameter", "/rolls/speed_m_per_s"},
           {"values", {10}},
           {"quantity", "amplitude"},
           {"amplitude", {{"window_s", 0.2}}}}}},
        {{"analysis", "roll_gap"}, {"scenario", {{"rolls", {{"flattening", "hitchcock"}}}}}},
        {{"analysis", "map"},
         {"options",
          {{"parameters",
            {{{"parameter", "/strip/reduction"}, {"values", {0.15, 0.25}}},
             {{"parameter", "/lubricant/viscosity_Pa_s"}, {"values", {0.0005}}}}},
           {"critical_speed", narrow}}}},
        {{"analysis", "calibrate"},
         {"options",
          {{"parameters", {{{"field", "/strip/flow_stress_MPa"}}}},
           {"observations",
            {{{"quantity", "roll_force_kN"}, {"value", 9000}, {"standard_uncertainty", 60}},
             {{"scenario", {{"strip", {{"reduction", 0.3}}}}},
              {"quantity", "roll_force_kN"},
              {"value", 11000},
              {"standard_uncertainty", 80}}}}}}},
        {{"analysis", "evaluate"},
         {"options", {{"critical_speed", narrow}, {"amplitude", {{"window_s", 0.2}}}}}},
        {{"analysis", "evaluate"},
         {"scenario", skids},
         {"options", {{"detail", "summary"}, {"critical_speed", narrow}}}},
    });
    for (const json& request : requests) {
        CAPTURE(request.dump());
        const service::Outcome outcome = service::evaluate(request);
        REQUIRE_MESSAGE(outcome.ok(), outcome.body.dump());
        std::string why;
        const bool valid = conforms(
            outcome.body, {{"$ref", "#/components/schemas/AnalysisResponse"}}, components, "", why);
        CHECK_MESSAGE(valid, why);
    }
    // The checker itself: a member the table does not write is refused.
    json tampered = service::evaluate({{"analysis", "roll_gap"}}).body;
    tampered["result"]["force_N"] = 1.0;
    std::string why;
    CHECK_FALSE(conforms(tampered, {{"$ref", "#/components/schemas/RollGapResponse"}}, components,
                         "", why));
    CHECK(why.find("force_N") != std::string::npos);
}
