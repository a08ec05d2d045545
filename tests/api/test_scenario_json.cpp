// The scenario document: engineering units in every name, derived from core's defaults,
// every field wired to its own member of core::Scenario, and an exact echo.

#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/units.h"
#include "support/approx.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::api;

namespace {

core::Scenario read_without_errors(const json& document) {
    FieldErrors errors;
    const core::Scenario scenario = scenario_from_json(document, "/scenario", errors);
    for (const FieldError& error : errors.reported())
        FAIL_CHECK(error.pointer << ": " << error.detail);
    return scenario;
}

// Every leaf of a JSON document as a pointer.
void collect_leaves(const json& node, const std::string& pointer, std::set<std::string>& leaves) {
    if (!node.is_object()) {
        leaves.insert(pointer);
        return;
    }
    for (const auto& [name, child] : node.items())
        collect_leaves(child, pointer + "/" + name, leaves);
}

double with_six_digits(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return std::strtod(text, nullptr);
}

// A valid value different from the default, in the field's unit.
json another_valid_value(const ScenarioField& field, const json& current) {
    switch (field.kind) {
        case FieldKind::boolean: return !current.get<bool>();
        case FieldKind::choice:
            for (const auto choice : field.choices) {
                if (choice != current.get<std::string>()) return std::string(choice);
            }
            return current;
        case FieldKind::integer: return current.get<int>() == 64 ? 128 : 64;
        case FieldKind::number: {
            const double value = current.get<double>();
            const double candidate = value == 0.0 ? 1.0 : with_six_digits(value * 0.9);
            return field.range.contains(candidate) ? candidate : with_six_digits(value * 1.05);
        }
    }
    return current;
}

}  // namespace

TEST_CASE("the default scenario document round-trips through core unchanged") {
    const json defaults = default_scenario_json();
    CHECK(resolved_scenario_json(read_without_errors(defaults)) == defaults);
}

TEST_CASE("the default scenario document is core::Scenario{} converted, field by field") {
    const json defaults = default_scenario_json();
    core::Scenario reference{};
    for (const ScenarioField& field : scenario_fields()) {
        CAPTURE(field.path);
        const json& value = defaults.at(json::json_pointer(field.path));
        switch (field.kind) {
            case FieldKind::number:
                CHECK(to_si(value.get<double>(), field.unit) ==
                      rollgap::test::approx(field.number(reference)).epsilon(1e-15));
                break;
            case FieldKind::integer: CHECK(value.get<int>() == field.integer(reference)); break;
            case FieldKind::boolean: CHECK(value.get<bool>() == field.flag(reference)); break;
            case FieldKind::choice:
                CHECK(value.get<std::string>() == field.read_choice(reference));
                break;
        }
    }
}

TEST_CASE("the default document holds exactly the schema's fields, each valid") {
    std::set<std::string> leaves;
    collect_leaves(default_scenario_json(), "", leaves);
    std::set<std::string> schema_paths;
    for (const ScenarioField& field : scenario_fields()) {
        CAPTURE(field.path);
        CHECK(schema_paths.insert(field.path).second);  // no duplicate rows
        if (field.kind == FieldKind::number || field.kind == FieldKind::integer) {
            CHECK(field.range.contains(
                default_scenario_json().at(json::json_pointer(field.path)).get<double>()));
        }
    }
    CHECK(leaves == schema_paths);
}

TEST_CASE("every number field name ends in its unit, except the dimensionless ones") {
    for (const ScenarioField& field : scenario_fields()) {
        if (field.kind != FieldKind::number || field.unit.code == units::one.code) continue;
        CAPTURE(field.path);
        const std::string name = field.path.substr(field.path.rfind('/') + 1);
        const std::string group = field.path.substr(0, field.path.rfind('/'));
        // Grouped fields (masses_t/m1, stiffness_GN_per_m/k1) carry the unit in the group name.
        const bool unit_in_name =
            name.find('_') != std::string::npos || group.find('_') != std::string::npos;
        CHECK(unit_in_name);
    }
}

TEST_CASE("each field is wired to its own member of core::Scenario") {
    const json defaults = default_scenario_json();
    for (const ScenarioField& field : scenario_fields()) {
        CAPTURE(field.path);
        const json::json_pointer at(field.path);
        json changed = defaults;
        changed[at] = another_valid_value(field, defaults[at]);
        REQUIRE(changed[at] != defaults[at]);
        const json echoed = resolved_scenario_json(read_without_errors(changed));
        // The change shows up at this field and nowhere else.
        CHECK(echoed == changed);
    }
}

TEST_CASE("engineering units are converted to SI") {
    const json document = {
        {"strip",
         {{"entry_thickness_mm", 2.5},
          {"flow_stress_MPa", 400},
          {"width_mm", 1200},
          {"youngs_modulus_GPa", 200}}},
        {"rolls", {{"radius_mm", 280}, {"speed_m_per_s", 12.5}}},
        {"lubricant", {{"viscosity_Pa_s", 0.03}, {"pressure_viscosity_per_MPa", 0.02}}},
        {"roughness", {{"roll_rq_um", 1.2}, {"strip_rq_um", 6}}},
        {"tension", {{"back", {{"stress_MPa", 40}, {"amplitude_MPa", 5}}}}},
        {"mill",
         {{"masses_t", {{"m3", 11}}},
          {"stiffness_GN_per_m", {{"k1", 25}}},
          {"damping_MN_s_per_m", {{"c1", 2}}}}},
    };
    const core::Scenario s = read_without_errors(document);
    CHECK(s.strip.entry_thickness == rollgap::test::approx(2.5e-3));
    CHECK(s.strip.flow_stress == rollgap::test::approx(400e6));
    CHECK(s.strip.width == rollgap::test::approx(1.2));
    CHECK(s.strip.youngs_modulus == rollgap::test::approx(200e9));
    CHECK(s.rolls.radius == rollgap::test::approx(0.28));
    CHECK(s.rolls.speed == rollgap::test::approx(12.5));
    CHECK(s.lubricant.viscosity == rollgap::test::approx(0.03));
    CHECK(s.lubricant.pressure_viscosity == rollgap::test::approx(0.02e-6));
    CHECK(s.roughness.roll_rq == rollgap::test::approx(1.2e-6));
    CHECK(s.roughness.strip_rq == rollgap::test::approx(6e-6));
    CHECK(s.tensions.back.stress == rollgap::test::approx(40e6));
    CHECK(s.tensions.back.amplitude == rollgap::test::approx(5e6));
    CHECK(s.structure.mass[2] == rollgap::test::approx(11e3));
    CHECK(s.structure.k1 == rollgap::test::approx(25e9));
    CHECK(s.structure.c1 == rollgap::test::approx(2e6));
}

TEST_CASE("choices map to core's enums") {
    const json document = {
        {"friction", {{"model", "coulomb"}, {"contact_model", "paper_fit"}}},
        {"inlet_film", {{"model", "eulerian"}}},
        {"tension", {{"back", {{"mode", "sinusoid"}}}, {"front", {{"mode", "span"}}}}},
    };
    const core::Scenario s = read_without_errors(document);
    CHECK(s.friction.model == core::FrictionModel::coulomb);
    CHECK(s.friction.contact == core::ContactModel::paper_fit);
    CHECK(s.inlet_film == core::InletFilmModel::eulerian);
    CHECK(s.tensions.back.mode == core::TensionMode::sinusoid);
    CHECK(s.tensions.front.mode == core::TensionMode::span);
}

TEST_CASE("missing fields keep core's defaults") {
    const core::Scenario s = read_without_errors({{"rolls", {{"speed_m_per_s", 5}}}});
    const core::Scenario reference{};
    CHECK(s.rolls.speed == 5.0);
    CHECK(s.rolls.radius == reference.rolls.radius);
    CHECK(s.strip.entry_thickness == reference.strip.entry_thickness);
    CHECK(s.tensions.back.mode == reference.tensions.back.mode);
}

TEST_CASE("a client's values are echoed exactly as sent, without conversion noise") {
    const json document = {{"strip", {{"entry_thickness_mm", 1.2345678901234}, {"reduction", 0.1}}},
                           {"roughness", {{"roll_rq_um", 0.3}}},
                           {"lubricant", {{"pressure_viscosity_per_MPa", 0.017}}}};
    const json echoed = resolved_scenario_json(read_without_errors(document));
    CHECK(echoed["strip"]["entry_thickness_mm"] == 1.2345678901234);
    CHECK(echoed["strip"]["reduction"] == 0.1);
    CHECK(echoed["roughness"]["roll_rq_um"] == 0.3);
    CHECK(echoed["lubricant"]["pressure_viscosity_per_MPa"] == 0.017);
}

TEST_CASE("an integral float is accepted for an integer field") {
    const core::Scenario s = read_without_errors({{"numerics", {{"bite_intervals", 128.0}}}});
    CHECK(s.numerics.bite_intervals == 128);
}

TEST_CASE("unit conversion gives the double nearest the decimal value, both ways") {
    // The same doubles as the literals in core, not 280 / 1000 with its rounding error.
    CHECK(to_si(280.0, units::millimetre) == 0.28);
    CHECK(to_si(1.6, units::millimetre) == 1.6e-3);
    CHECK(to_si(1.7, units::per_megapascal) == 1.7e-6);
    CHECK(to_si(380.0, units::megapascal) == 380e6);
    CHECK(from_si(1.6e-3, units::millimetre) == 1.6);
    CHECK(from_si(1.7e-6, units::per_megapascal) == 1.7);
    CHECK(from_si(5.5e-4, units::pascal_second) == 5.5e-4);
    CHECK(to_si(0.0, units::megapascal) == 0.0);
    CHECK(to_si(-2.5, units::megapascal) == -2.5e6);
}

TEST_CASE("values of up to 15 significant digits survive SI and back bit for bit") {
    std::mt19937_64 random(20240611);
    std::uniform_real_distribution<double> mantissa(1.0, 10.0);
    std::uniform_int_distribution<int> exponent(-8, 8);
    const Unit all_units[] = {units::millimetre,
                              units::micrometre,
                              units::megapascal,
                              units::gigapascal,
                              units::per_megapascal,
                              units::tonne,
                              units::meganewton_second_per_metre};
    for (int i = 0; i < 20000; ++i) {
        char text[40];
        std::snprintf(text, sizeof text, "%.14fe%d", mantissa(random), exponent(random));
        const double value = std::strtod(text, nullptr);
        for (const Unit unit : all_units) {
            CAPTURE(text);
            CAPTURE(unit.code);
            REQUIRE(from_si(to_si(value, unit), unit) == value);
        }
    }
}

TEST_CASE("numbers in messages") {
    CHECK(format_number(0.05) == "0.05");
    CHECK(format_number(100000.0) == "100000");
    CHECK(format_number(1e-8) == "1e-08");
}
