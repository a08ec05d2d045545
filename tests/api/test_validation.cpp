// Strict validation of the scenario: every violation is reported, each with the JSON pointer
// of the offending field, the bound and the unit.

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <variant>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/json_text.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::api;

namespace {

FieldErrors validate(const json& patch) {
    FieldErrors errors;
    scenario_from_patch(patch, "/scenario", errors);
    return errors;
}

std::optional<FieldError> error_at(const FieldErrors& errors, const std::string& pointer) {
    for (const FieldError& error : errors.reported()) {
        if (error.pointer == pointer) return error;
    }
    return std::nullopt;
}

// A patch setting one field (path relative to the scenario) to `value`.
json patch_setting(const std::string& path, const json& value) {
    json patch = json::object();
    patch[json::json_pointer(path)] = value;
    return patch;
}

}  // namespace

TEST_CASE("an unknown field is an error at its pointer, with the intended field suggested") {
    const FieldErrors errors = validate({{"strip", {{"entry_thickness_m", 0.0016}}}});
    REQUIRE(errors.size() == 1);
    const FieldError& error = errors.reported()[0];
    CHECK(error.pointer == "/scenario/strip/entry_thickness_m");
    CHECK(error.detail.find("did you mean 'entry_thickness_mm'") != std::string::npos);
    CHECK_FALSE(error.bound.has_value());
}

TEST_CASE("unknown fields are rejected at every level") {
    const FieldErrors errors = validate({{"rolls", {{"speed_mps", 10}}},
                                         {"stripp", json::object()},
                                         {"tension", {{"back", {{"stress_Pa", 1}}}}},
                                         {"mill", {{"stiffness_GN_per_m", {{"k4", 3}}}}}});
    CHECK(errors.size() == 4);
    CHECK(error_at(errors, "/scenario/rolls/speed_mps"));
    CHECK(error_at(errors, "/scenario/stripp")->detail.find("did you mean 'strip'") !=
          std::string::npos);
    CHECK(error_at(errors, "/scenario/tension/back/stress_Pa")->detail.find("stress_MPa") !=
          std::string::npos);
    CHECK(error_at(errors, "/scenario/mill/stiffness_GN_per_m/k4")->detail.find("not an input") !=
          std::string::npos);
}

TEST_CASE("a field name with '/' or '~' is escaped in the pointer (RFC 6901)") {
    const FieldErrors errors = validate({{"strip", {{"a/b~c", 1}}}});
    REQUIRE(errors.size() == 1);
    CHECK(errors.reported()[0].pointer == "/scenario/strip/a~1b~0c");
}

TEST_CASE("wrong types are errors at the field") {
    const FieldErrors errors =
        validate({{"strip", {{"flow_stress_MPa", "380"}, {"reduction", nullptr}}},
                  {"rolls", {{"radius_mm", json::array({280})}}},
                  {"lubricant", {{"limiting_shear", 1}}},
                  {"friction", {{"model", 2}}},
                  {"numerics", 64}});
    // reduction: null in a merge patch restores the default, so it is no error.
    CHECK(errors.size() == 5);
    CHECK(error_at(errors, "/scenario/strip/flow_stress_MPa")->detail ==
          "must be a number, got string");
    CHECK(error_at(errors, "/scenario/rolls/radius_mm")->detail == "must be a number, got array");
    CHECK(error_at(errors, "/scenario/lubricant/limiting_shear")->detail ==
          "must be a boolean, got number");
    CHECK(error_at(errors, "/scenario/friction/model"));
    CHECK(error_at(errors, "/scenario/numerics")->detail == "must be an object, got number");
}

TEST_CASE("a scenario that is not an object is one error at /scenario") {
    const FieldErrors errors = validate(json::array({1, 2, 3}));
    REQUIRE(errors.size() == 1);
    CHECK(errors.reported()[0].pointer == "/scenario");
}

TEST_CASE("an unknown choice lists the allowed values as the bound") {
    const FieldErrors errors =
        validate({{"friction", {{"model", "Coulomb"}}}, {"inlet_film", {{"model", "euler"}}}});
    REQUIRE(errors.size() == 2);
    const auto friction = error_at(errors, "/scenario/friction/model");
    CHECK(friction->bound == "mixed | coulomb");
    CHECK(friction->detail.find("did you mean 'coulomb'") != std::string::npos);
    CHECK(error_at(errors, "/scenario/inlet_film/model")->bound == "paper | eulerian");
}

TEST_CASE(
    "every numeric field rejects values just outside its bounds, with pointer, bound and unit") {
    for (const ScenarioField& field : scenario_fields()) {
        if (field.kind != FieldKind::number && field.kind != FieldKind::integer) continue;
        const std::string pointer = "/scenario" + field.path;
        CAPTURE(pointer);
        const double step =
            field.kind == FieldKind::integer ? 2.0 : std::abs(field.range.max) * 1e-9 + 1e-12;
        const double below = field.range.min_open ? field.range.min : field.range.min - step;
        const double above = field.range.max_open ? field.range.max : field.range.max + step;
        for (const double outside : {below, above}) {
            CAPTURE(outside);
            const FieldErrors errors = validate(patch_setting(field.path, outside));
            const auto error = error_at(errors, pointer);
            REQUIRE(error.has_value());
            CHECK(error->bound->find(field.range.text()) == 0);
            CHECK(error->unit == std::string(field.unit.code));
        }
        // The bounds themselves, where closed, are valid (cross-field rules aside).
        if (!field.range.min_open && field.path.find("tension") == std::string::npos) {
            CHECK_FALSE(error_at(validate(patch_setting(field.path, field.range.min)), pointer));
        }
    }
}

TEST_CASE("bounds are checked in the unit of the field name") {
    // A thickness given in metres instead of millimetres lands outside the bounds.
    const auto error = error_at(validate({{"strip", {{"entry_thickness_mm", 0.0016}}}}),
                                "/scenario/strip/entry_thickness_mm");
    REQUIRE(error);
    CHECK(error->bound == "[0.05, 20]");
    CHECK(error->unit == "mm");
    // The open end of the reduction: 0 is no reduction.
    const auto reduction =
        error_at(validate({{"strip", {{"reduction", 0}}}}), "/scenario/strip/reduction");
    REQUIRE(reduction);
    CHECK(reduction->bound == "(0, 0.7]");
    CHECK(reduction->unit == "1");
}

TEST_CASE("bite_intervals must be an even integer") {
    const std::string pointer = "/scenario/numerics/bite_intervals";
    CHECK(error_at(validate({{"numerics", {{"bite_intervals", 33}}}}), pointer)->bound ==
          "[8, 4096], even");
    CHECK(error_at(validate({{"numerics", {{"bite_intervals", 64.5}}}}), pointer)->detail ==
          "must be an integer");
    CHECK(error_at(validate({{"numerics", {{"bite_intervals", 6}}}}), pointer));
    CHECK(validate({{"numerics", {{"bite_intervals", 64}}}}).empty());
}

TEST_CASE("tension must stay below the flow stress") {
    const std::string pointer = "/scenario/tension/back/stress_MPa";
    SUBCASE("at the flow stress") {
        const auto error =
            error_at(validate({{"tension", {{"back", {{"stress_MPa", 380}}}}}}), pointer);
        REQUIRE(error);
        CHECK(error->bound == "[0, 380)");
        CHECK(error->unit == "MPa");
        CHECK(error->detail.find("flow stress") != std::string::npos);
    }
    SUBCASE("just below it is valid") {
        CHECK(validate({{"tension", {{"back", {{"stress_MPa", 379.9}}}}}}).empty());
    }
    SUBCASE("against the flow stress of the same request, not the default") {
        const FieldErrors errors = validate({{"strip", {{"flow_stress_MPa", 15}}}});
        REQUIRE(errors.size() == 1);  // the default back tension, 18 MPa
        CHECK(errors.reported()[0].pointer == pointer);
        CHECK(errors.reported()[0].bound == "[0, 15)");
    }
    SUBCASE("front tension too") {
        CHECK(error_at(validate({{"tension", {{"front", {{"stress_MPa", 400}}}}}}),
                       "/scenario/tension/front/stress_MPa"));
    }
    SUBCASE("not checked against a flow stress that is itself invalid") {
        const FieldErrors errors = validate({{"strip", {{"flow_stress_MPa", -1}}}});
        CHECK(errors.size() == 1);
        CHECK(error_at(errors, "/scenario/strip/flow_stress_MPa"));
    }
}

TEST_CASE("a sinusoidal tension must neither go slack nor reach the flow stress") {
    const std::string pointer = "/scenario/tension/back/amplitude_MPa";
    const auto sinusoid = [](double mean, double amplitude) {
        return json{
            {"tension",
             {{"back",
               {{"mode", "sinusoid"}, {"stress_MPa", mean}, {"amplitude_MPa", amplitude}}}}}};
    };
    CHECK(validate(sinusoid(18, 9)).empty());
    const auto slack = error_at(validate(sinusoid(18, 20)), pointer);
    REQUIRE(slack);
    CHECK(slack->bound == "[0, 18]");
    CHECK(slack->unit == "MPa");
    const auto yielding = error_at(validate(sinusoid(300, 100)), pointer);
    REQUIRE(yielding);
    CHECK(yielding->bound == "[0, 80)");
    // In other modes the amplitude is unused and only its own bounds apply.
    CHECK(validate({{"tension",
                     {{"back", {{"mode", "constant"}, {"stress_MPa", 0}, {"amplitude_MPa", 9}}}}}})
              .empty());
}

TEST_CASE("the bite angle must stay small enough for the parabolic roll profile") {
    const auto error =
        error_at(validate({{"strip", {{"entry_thickness_mm", 20}, {"reduction", 0.7}}},
                           {"rolls", {{"radius_mm", 10}}}}),
                 "/scenario/strip/reduction");
    REQUIRE(error);
    CHECK(error->bound == "(0, 0.0612]");  // 0.35^2 × 10 mm / 20 mm, rounded down
    CHECK(error->unit == "1");
    CHECK(validate({{"strip", {{"entry_thickness_mm", 20}, {"reduction", 0.06}}},
                    {"rolls", {{"radius_mm", 10}}}})
              .empty());
}

TEST_CASE("the Rayleigh frequencies must be in order") {
    const auto error = error_at(validate({{"mill", {{"rayleigh", {{"low_frequency_Hz", 500}}}}}}),
                                "/scenario/mill/rayleigh/high_frequency_Hz");
    REQUIRE(error);
    CHECK(error->bound == "(500, 100000]");
    CHECK(error->unit == "Hz");
}

TEST_CASE("all violations are reported, not only the first") {
    const FieldErrors errors = validate({{"strip", {{"reduction", 0.9}, {"width_mm", 1}}},
                                         {"rolls", {{"speed_m_per_s", 0}}},
                                         {"roughness", {{"roll_rq_um", 100}}},
                                         {"friction", {{"coulomb_coefficient", 2}}}});
    CHECK(errors.size() == 5);
}

TEST_CASE("huge and non-finite numbers are rejected") {
    SUBCASE("1e308 is a number, but out of bounds") {
        const auto error =
            error_at(validate({{"strip", {{"width_mm", 1e308}}}}), "/scenario/strip/width_mm");
        REQUIRE(error);
        CHECK(error->bound == "[10, 5000]");
    }
    SUBCASE("1e999 in request text is invalid JSON, not infinity") {
        const auto parsed = parse_json_text(R"({"scenario": {"strip": {"width_mm": 1e999}}})");
        REQUIRE(std::holds_alternative<Problem>(parsed));
        CHECK(std::get<Problem>(parsed).code == ProblemCode::invalid_json);
        CHECK(std::get<Problem>(parsed).detail.find("1e999") != std::string::npos);
    }
    SUBCASE("infinity and NaN in JSON built in code") {
        const FieldErrors errors =
            validate({{"strip", {{"width_mm", std::numeric_limits<double>::infinity()}}},
                      {"rolls", {{"speed_m_per_s", std::nan("")}}}});
        CHECK(errors.size() == 2);
        CHECK(error_at(errors, "/scenario/strip/width_mm")->detail == "must be a finite number");
        CHECK(error_at(errors, "/scenario/rolls/speed_m_per_s")->detail ==
              "must be a finite number");
    }
    SUBCASE("a huge integer for an integer field") {
        CHECK(error_at(validate({{"numerics", {{"bite_intervals", 18446744073709551615ULL}}}}),
                       "/scenario/numerics/bite_intervals"));
    }
}

TEST_CASE("request text is limited in nesting and may not repeat keys") {
    SUBCASE("deep nesting is refused without recursion trouble") {
        const std::string deep = std::string(100000, '[') + std::string(100000, ']');
        const auto parsed = parse_json_text(deep);
        REQUIRE(std::holds_alternative<Problem>(parsed));
        CHECK(std::get<Problem>(parsed).code == ProblemCode::invalid_json);
    }
    SUBCASE("nesting up to the limit is fine") {
        const std::string deep =
            std::string(max_json_depth, '[') + std::string(max_json_depth, ']');
        CHECK(std::holds_alternative<json>(parse_json_text(deep)));
        const std::string too_deep = "[" + deep + "]";
        CHECK(std::holds_alternative<Problem>(parse_json_text(too_deep)));
    }
    SUBCASE("nesting depth of a value built in code") {
        json deep = 1;
        for (int i = 0; i < 10000; ++i) deep = json::array({std::move(deep)});
        CHECK(nests_deeper_than(deep, max_json_depth));
        CHECK_FALSE(nests_deeper_than(default_scenario_json(), max_json_depth));
    }
    SUBCASE("a duplicate key is an error, not a silent last-one-wins") {
        const auto parsed =
            parse_json_text(R"({"scenario": {"strip": {"reduction": 0.1, "reduction": 0.5}}})");
        REQUIRE(std::holds_alternative<Problem>(parsed));
        CHECK(std::get<Problem>(parsed).detail.find("duplicate key 'reduction'") !=
              std::string::npos);
        CHECK(std::holds_alternative<json>(parse_json_text(R"([{"a": 1}, {"a": 2}])")));
    }
    SUBCASE("syntax errors") {
        const auto parsed = parse_json_text(R"({"scenario": )");
        REQUIRE(std::holds_alternative<Problem>(parsed));
        CHECK(std::get<Problem>(parsed).detail.find("json.exception") == std::string::npos);
    }
}

TEST_CASE("a flood of violations is capped, and the rest counted") {
    json strip = json::object();
    for (int i = 0; i < 1000; ++i) strip["unknown_" + std::to_string(i)] = i;
    const FieldErrors errors = validate({{"strip", strip}});
    CHECK(errors.size() == 1000);
    CHECK(errors.reported().size() == FieldErrors::default_reporting_cap);
    const Problem problem = errors.to_problem(ProblemCode::invalid_scenario, "many");
    CHECK(problem.errors_omitted == 1000 - FieldErrors::default_reporting_cap);
}
