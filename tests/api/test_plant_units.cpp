// Plant units (api/plant_units.h): a member given under its plant unit's key is the same
// scenario as the canonical member with the converted value — bit for bit where the factor is a
// power of ten (the decimal is shifted, not multiplied) — and the echo is canonical; two forms
// of one member, or an alternate that is not a number, are refused at their pointers; the
// mill's own members, its shared stand and each stand, a batch's items and a calibration's
// observations are rewritten where they sit.

#include <doctest/doctest.h>

#include "support/approx.h"

#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/plant_units.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/tandem_json.h"
#include "api/tandem_schema.h"

using nlohmann::json;
using namespace rollgap;

namespace plant_units_test {

// The resolved (echoed) document of a scenario patch after the plant-unit rewrite.
json resolved(json patch) {
    api::FieldErrors errors;
    api::canonicalise_scenario_patch(patch, "/scenario", errors);
    const core::Scenario scenario = api::scenario_from_patch(patch, "/scenario", errors);
    std::string reported;
    for (const auto& e : errors.reported()) reported += e.pointer + ": " + e.detail + "\n";
    INFO(reported);
    REQUIRE(errors.empty());
    return api::resolved_scenario_json(scenario);
}

std::set<std::string> error_pointers(const api::FieldErrors& errors) {
    std::set<std::string> pointers;
    for (const auto& e : errors.reported()) pointers.insert(e.pointer);
    return pointers;
}

}  // namespace plant_units_test

namespace put = plant_units_test;

TEST_CASE("plant units: each alternate is the canonical member with the converted value") {
    struct Case {
        json alternate, canonical;
    };
    const Case cases[] = {
        {{{"rolls", {{"speed_m_per_min", 900}}}}, {{"rolls", {{"speed_m_per_s", 15}}}}},
        {{{"rolls", {{"speed_m_per_min", 1000}}}}, {{"rolls", {{"speed_m_per_s", 1000.0 / 60.0}}}}},
        {{{"rolls", {{"speed_mm_per_s", 250}}}}, {{"rolls", {{"speed_m_per_s", 0.25}}}}},
        // 0.55 / 1000 in binary is not the double of 0.00055; the shifted decimal is
        {{{"lubricant", {{"viscosity_mPa_s", 0.55}}}},
         {{"lubricant", {{"viscosity_Pa_s", 0.00055}}}}},
        {{{"lubricant", {{"viscosity_mPa_s", 1.7}}}},
         {{"lubricant", {{"viscosity_Pa_s", 0.0017}}}}},
        {{{"rolls", {{"diameter_mm", 561}}}}, {{"rolls", {{"radius_mm", 280.5}}}}},
        {{{"mill", {{"masses_kg", {{"m1", 40500}, {"m3", 11000}}}}}},
         {{"mill", {{"masses_t", {{"m1", 40.5}, {"m3", 11}}}}}}},
        {{{"mill", {{"stiffness_kN_per_mm", {{"k2", 30100}}}}}},
         {{"mill", {{"stiffness_GN_per_m", {{"k2", 30.1}}}}}}},
        {{{"mill", {{"damping_kN_s_per_m", {{"c2", 150}}}}}},
         {{"mill", {{"damping_MN_s_per_m", {{"c2", 0.15}}}}}}},
    };
    for (const Case& c : cases) {
        CAPTURE(c.alternate.dump());
        const json echoed = put::resolved(c.alternate);
        CHECK(echoed == put::resolved(c.canonical));                // doubles compared exactly
        CHECK(echoed.dump().find("per_min") == std::string::npos);  // the echo is canonical
    }
    // the echo of an alternate read back is the same scenario
    const json echoed =
        put::resolved({{"rolls", {{"speed_m_per_min", 900}, {"diameter_mm", 600}}}});
    CHECK(echoed["rolls"]["speed_m_per_s"] == 15.0);
    CHECK(echoed["rolls"]["radius_mm"] == 300.0);
    CHECK(put::resolved(echoed) == echoed);
}

TEST_CASE("plant units: null restores the default, several forms and non-numbers are refused") {
    CHECK(put::resolved({{"rolls", {{"speed_m_per_min", nullptr}}}}) ==
          put::resolved(json::object()));

    api::FieldErrors errors;
    json both = {{"rolls", {{"speed_m_per_s", 15}, {"speed_m_per_min", 900}}},
                 {"lubricant", {{"viscosity_mPa_s", "thin"}}},
                 {"mill", {{"masses_kg", {{"m1", "heavy"}}}, {"stiffness_kN_per_mm", 5}}}};
    api::canonicalise_scenario_patch(both, "/scenario", errors);
    CHECK(put::error_pointers(errors) ==
          std::set<std::string>{"/scenario/rolls/speed_m_per_s", "/scenario/rolls/speed_m_per_min",
                                "/scenario/lubricant/viscosity_mPa_s",
                                "/scenario/mill/masses_kg/m1",
                                "/scenario/mill/stiffness_kN_per_mm"});
    for (const auto& e : errors.reported()) {
        CAPTURE(e.pointer);
        if (e.pointer.starts_with("/scenario/rolls"))
            CHECK(e.detail.find("speed_m_per_s, speed_m_per_min") != std::string::npos);
        if (e.pointer == "/scenario/lubricant/viscosity_mPa_s") CHECK(e.unit == "mPa.s");
    }
    // two alternates of one member are as ambiguous as an alternate beside the canonical one
    api::FieldErrors two;
    json alternates = {{"rolls", {{"speed_mm_per_s", 15000}, {"speed_m_per_min", 900}}}};
    api::canonicalise_scenario_patch(alternates, "", two);
    CHECK(put::error_pointers(two) ==
          std::set<std::string>{"/rolls/speed_mm_per_s", "/rolls/speed_m_per_min"});
    // a key that is no alternate stays for the strict reader ("did you mean")
    api::FieldErrors unknown;
    json typo = {{"rolls", {{"speed_km_per_h", 54}}}};
    api::canonicalise_scenario_patch(typo, "", unknown);
    CHECK(unknown.empty());
    CHECK(typo["rolls"].contains("speed_km_per_h"));
}

TEST_CASE("plant units: the mill's members, its shared stand and each stand, where they sit") {
    const json alternate = {{"speed_m_per_min", 720},
                            {"stand_defaults", {{"lubricant", {{"viscosity_mPa_s", 0.8}}}}},
                            {"stands",
                             {json::object(),
                              {{"rolls", {{"diameter_mm", 500}}}},
                              json::object(),
                              json::object(),
                              json::object()}}};
    const json canonical = {{"speed_m_per_s", 12},
                            {"stand_defaults", {{"lubricant", {{"viscosity_Pa_s", 0.0008}}}}},
                            {"stands",
                             {json::object(),
                              {{"rolls", {{"radius_mm", 250}}}},
                              json::object(),
                              json::object(),
                              json::object()}}};
    json rewritten = alternate;
    api::FieldErrors errors;
    api::canonicalise_tandem_patch(rewritten, "/tandem", errors);
    CHECK(errors.empty());
    CHECK(rewritten == canonical);
    const core::Mill mill = api::mill_from_patch(rewritten, "/tandem", errors);
    REQUIRE(errors.empty());
    CHECK(api::resolved_tandem_json(mill) ==
          api::resolved_tandem_json(api::mill_from_patch(canonical, "/tandem", errors)));

    api::FieldErrors twice;
    json doubled = {
        {"stands", {json::object(), {{"rolls", {{"radius_mm", 250}, {"diameter_mm", 500}}}}}}};
    api::canonicalise_tandem_patch(doubled, "/tandem", twice);
    CHECK(put::error_pointers(twice) ==
          std::set<std::string>{"/tandem/stands/1/rolls/radius_mm",
                                "/tandem/stands/1/rolls/diameter_mm"});
}

TEST_CASE("plant units: every scenario and mill a request carries, a batch's and a fit's too") {
    json request = {
        {"analysis", "batch"},
        {"options",
         {{"analysis", "speed_limit"},
          {"scenario", {{"rolls", {{"speed_m_per_min", 600}}}}},
          {"items",
           {{{"label", "C-1"}, {"scenario", {{"lubricant", {{"viscosity_mPa_s", 1.2}}}}}},
            {{"label", "C-2"}, {"tandem", {{"speed_m_per_min", 900}}}}}},
          {"observations", {{{"scenario", {{"rolls", {{"speed_mm_per_s", 12000}}}}}}}}}}};
    api::FieldErrors errors;
    api::canonicalise_request_units(request, "", errors);
    CHECK(errors.empty());
    const json& o = request["options"];
    CHECK(o["scenario"]["rolls"] == json{{"speed_m_per_s", 10}});
    CHECK(o["items"][0]["scenario"]["lubricant"] == json{{"viscosity_Pa_s", 0.0012}});
    CHECK(o["items"][1]["tandem"] == json{{"speed_m_per_s", 15}});
    CHECK(o["observations"][0]["scenario"]["rolls"] == json{{"speed_m_per_s", 12}});
    CHECK(o["items"][0]["label"] == "C-1");  // nothing else touched

    json clash = {
        {"options",
         {{"items",
           {json::object(),
            {{"scenario", {{"rolls", {{"speed_m_per_s", 1}, {"speed_m_per_min", 60}}}}}}}}}}};
    api::FieldErrors refused;
    api::canonicalise_request_units(clash, "", refused);
    CHECK(put::error_pointers(refused).contains("/options/items/1/scenario/rolls/speed_m_per_min"));
}

TEST_CASE("plant units: every row of the table names members that exist") {
    for (const api::AlternateUnit& unit : api::alternate_units()) {
        CAPTURE(unit.alternate);
        bool used = false;
        const auto check = [&](std::string_view path) {
            const std::string_view member = path.substr(path.rfind('/') + 1);
            for (const auto& [alternate, row] : api::alternates_of(member))
                if (row == &unit) used = true;
        };
        for (const api::ScenarioField& field : api::scenario_fields()) {
            check(field.path);
            check(field.path.substr(0, field.path.rfind('/')));  // its group
        }
        for (const api::TandemField& field : api::tandem_fields()) check(field.path);
        CHECK(used);
        // the alternate is no canonical member itself
        for (const api::ScenarioField& field : api::scenario_fields())
            CHECK(field.path.find(std::string(unit.alternate) + "/") == std::string::npos);
    }
}

TEST_CASE("plant units: a value outside its typical range is a warning naming the likely unit") {
    // the defaults are typical: no warning for the default stand or mill
    CHECK(api::typical_range_warnings(core::Scenario{}, "/scenario").empty());
    api::FieldErrors none;
    const core::Mill default_mill = api::mill_from_patch(json::object(), "/tandem", none);
    REQUIRE(none.empty());
    CHECK(api::typical_range_warnings(default_mill, "/tandem").empty());

    struct Case {
        json patch;
        std::string pointer;
        std::optional<std::string> key;  // the likely plant unit's key
        double meant;                    // the value in the field's unit it would be
    };
    const Case cases[] = {
        {{{"rolls", {{"speed_m_per_s", 90}}}},
         "/scenario/rolls/speed_m_per_s",
         "speed_m_per_min",
         1.5},
        {{{"rolls", {{"radius_mm", 560}}}}, "/scenario/rolls/radius_mm", "diameter_mm", 280},
        {{{"lubricant", {{"viscosity_Pa_s", 0.55}}}},
         "/scenario/lubricant/viscosity_Pa_s",
         "viscosity_mPa_s",
         0.00055},
        {{{"mill", {{"masses_t", {{"m3", 5000}}}}}},
         "/scenario/mill/masses_t/m3",
         "masses_kg/m3",
         5},
        {{{"strip", {{"width_mm", 4000}}}}, "/scenario/strip/width_mm", std::nullopt, 0},
    };
    for (const Case& c : cases) {
        CAPTURE(c.pointer);
        api::FieldErrors errors;
        const core::Scenario scenario = api::scenario_from_patch(c.patch, "/scenario", errors);
        REQUIRE(errors.empty());  // accepted: within the hard bounds
        const json warnings = api::typical_range_warnings(scenario, "/scenario");
        REQUIRE(warnings.size() == 1);
        const json& w = warnings[0];
        CHECK(w["pointer"] == c.pointer);
        CHECK(w["detail"].get<std::string>().find("used as given") != std::string::npos);
        const api::ScenarioField* field =
            api::find_scenario_field(c.pointer.substr(std::string("/scenario").size()));
        REQUIRE(field != nullptr);
        CHECK(w["typical"] == field->typical->text());
        if (c.key) {
            CHECK(w["likely"]["key"] == *c.key);
            CHECK(w["likely"]["value"].get<double>() == c.meant);
            // the likely value is typical, and sending it under that key gives no warning
            CHECK(field->typical->contains(c.meant));
        } else {
            CHECK_FALSE(w.contains("likely"));
        }
    }
    // the mill's speed, and a stand's own field at its stand's pointer
    api::FieldErrors errors;
    const core::Mill mill = api::mill_from_patch(
        {{"speed_m_per_s", 60},
         {"stands", {json::object(), json::object(), {{"rolls", {{"radius_mm", 600}}}}}},
         {"entry_thickness_mm", 2.8},
         {"exit_thickness_mm", {2.2, 1.8, 1.5}},
         {"spans", {{"length_m", {5, 5}}, {"tension_MPa", {60, 60}}}}},
        "/tandem", errors);
    std::string reported;
    for (const auto& e : errors.reported()) reported += e.pointer + ": " + e.detail + "\n";
    INFO(reported);
    REQUIRE(errors.empty());
    const json warnings = api::typical_range_warnings(mill, "/tandem");
    std::set<std::string> pointers;
    for (const json& w : warnings) pointers.insert(w["pointer"].get<std::string>());
    CHECK(pointers ==
          std::set<std::string>{"/tandem/speed_m_per_s", "/tandem/stands/2/rolls/radius_mm"});
}

TEST_CASE("plant units: a value beyond the hard bound says which plant unit would fit") {
    api::FieldErrors errors;
    (void)api::scenario_from_patch({{"rolls", {{"speed_m_per_s", 900}}}}, "/scenario", errors);
    REQUIRE(errors.reported().size() == 1);
    const auto& e = errors.reported()[0];
    CHECK(e.pointer == "/scenario/rolls/speed_m_per_s");
    CHECK(e.detail.find("is outside [0.01, 100] m/s") != std::string::npos);
    CHECK(e.detail.find("if 900 m/min was meant, that is 15 m/s: send it as speed_m_per_min") !=
          std::string::npos);
    CHECK(e.bound == "[0.01, 100]");
    api::FieldErrors mill_errors;
    (void)api::mill_from_patch({{"speed_m_per_s", 900}}, "/tandem", mill_errors);
    REQUIRE_FALSE(mill_errors.empty());
    CHECK(mill_errors.reported()[0].pointer == "/tandem/speed_m_per_s");
    CHECK(mill_errors.reported()[0].detail.find("send it as speed_m_per_min") != std::string::npos);
    // no plant unit fits: the plain bound
    api::FieldErrors plain;
    (void)api::scenario_from_patch({{"rolls", {{"speed_m_per_s", 1e7}}}}, "/scenario", plain);
    REQUIRE(plain.reported().size() == 1);
    CHECK(plain.reported()[0].detail.find("send it as") == std::string::npos);
}

TEST_CASE("plant units: a tension in kN is that force over the strip's cross-section on its side") {
    // σ = F / (w · h): the back side over the entry thickness, the front over the exit one
    const auto read = [](json patch, api::FieldErrors& errors) {
        api::canonicalise_scenario_patch(patch, "/scenario", errors);
        return api::scenario_from_patch(patch, "/scenario", errors);
    };
    api::FieldErrors none;
    const core::Scenario forces = read(
        {{"strip", {{"width_mm", 1250}, {"entry_thickness_mm", 2.4}, {"reduction", 0.3}}},
         {"tension",
          {{"back", {{"force_kN", 150}, {"amplitude_kN", 30}}}, {"front", {{"force_kN", 210}}}}}},
        none);
    REQUIRE(none.empty());
    const double entry_area = 1.25 * 2.4e-3, exit_area = 1.25 * 2.4e-3 * (1.0 - 0.3);
    CHECK(forces.tensions.back.stress == rollgap::test::approx(150e3 / entry_area).epsilon(1e-14));
    CHECK(forces.tensions.back.amplitude ==
          rollgap::test::approx(30e3 / entry_area).epsilon(1e-14));
    CHECK(forces.tensions.front.stress == rollgap::test::approx(210e3 / exit_area).epsilon(1e-14));
    // the echo is the stress, and read back it is the same scenario
    const json echoed = api::resolved_scenario_json(forces);
    CHECK_FALSE(echoed["tension"]["back"].contains("force_kN"));
    api::FieldErrors again;
    CHECK(api::resolved_scenario_json(read(echoed, again)) == echoed);
    CHECK(again.empty());

    // Layers: the strip from one, the force from another, merged in either order of forms;
    // the later layer's form wins.
    const auto layered = [&](json base, json over) {
        api::FieldErrors errors;
        api::canonicalise_scenario_patch(base, "/scenario", errors);
        api::canonicalise_scenario_patch(over, "/scenario", errors);
        base.merge_patch(over);
        const core::Scenario scenario = api::scenario_from_patch(base, "/scenario", errors);
        CHECK(errors.empty());
        return scenario.tensions.back.stress;
    };
    const double default_area = 1.8 * 1.6e-3;
    CHECK(layered({{"tension", {{"back", {{"stress_MPa", 40}}}}}},
                  {{"tension", {{"back", {{"force_kN", 100}}}}}}) ==
          rollgap::test::approx(100e3 / default_area).epsilon(1e-14));
    CHECK(layered({{"tension", {{"back", {{"force_kN", 100}}}}}},
                  {{"tension", {{"back", {{"stress_MPa", 40}}}}}}) ==
          rollgap::test::approx(40e6).epsilon(1e-15));
    CHECK(layered({{"tension", {{"back", {{"force_kN", 100}}}}}},
                  {{"strip", {{"width_mm", 1000}}}}) ==
          rollgap::test::approx(100e3 / (1.0 * 1.6e-3)).epsilon(1e-14));
    // null in the later layer takes the force away: the default stress again
    CHECK(layered({{"tension", {{"back", {{"force_kN", 100}}}}}},
                  {{"tension", {{"back", {{"force_kN", nullptr}, {"stress_MPa", nullptr}}}}}}) ==
          rollgap::test::approx(core::Scenario{}.tensions.back.stress).epsilon(1e-15));
    // rewriting twice changes nothing (a stored layer is read again)
    json twice = {{"tension", {{"back", {{"force_kN", 100}}}, {"front", {{"stress_MPa", 20}}}}}};
    api::FieldErrors first_errors, second_errors;
    api::canonicalise_scenario_patch(twice, "", first_errors);
    const json once = twice;
    api::canonicalise_scenario_patch(twice, "", second_errors);
    CHECK(twice == once);
    CHECK(first_errors.empty());
    CHECK(second_errors.empty());

    // Both forms in one layer, a force that is no number, a force beyond the stress's bound
    api::FieldErrors refused;
    (void)read(
        {{"tension",
          {{"back", {{"stress_MPa", 40}, {"force_kN", 100}}}, {"front", {{"force_kN", "high"}}}}}},
        refused);
    CHECK(put::error_pointers(refused) ==
          std::set<std::string>{"/scenario/tension/back/stress_MPa",
                                "/scenario/tension/back/force_kN",
                                "/scenario/tension/front/force_kN"});
    api::FieldErrors beyond;
    // 3000 MPa (the bound, open) over 2.88e-3 m² is 8640 kN
    (void)read({{"tension", {{"back", {{"force_kN", 9000}}}}}}, beyond);
    REQUIRE(beyond.reported().size() == 1);
    const api::FieldError& error = beyond.reported().front();
    CHECK(error.pointer == "/scenario/tension/back/force_kN");
    CHECK(error.unit == "kN");
    REQUIRE(error.bound.has_value());
    CHECK(error.bound->starts_with("[0, "));
    CHECK(error.bound->ends_with(")"));
    CHECK(std::stod(error.bound->substr(4)) == rollgap::test::approx(8640.0).epsilon(1e-12));
    CHECK(error.detail.find("outside [0, 3000) MPa") != std::string::npos);

    // In a mill the tensions are the mill's: a stand's force is refused like its stress.
    api::FieldErrors mill_errors;
    json mill = {{"stands", {json::object(), {{"tension", {{"back", {{"force_kN", 100}}}}}}}}};
    api::canonicalise_tandem_patch(mill, "/tandem", mill_errors);
    (void)api::mill_from_patch(mill, "/tandem", mill_errors);
    CHECK(put::error_pointers(mill_errors).contains("/tandem/stands/1/tension"));
}

TEST_CASE("plant units: a tension far above the typical stresses warns that it is likely kN") {
    api::FieldErrors errors;
    // hard strip, so that 600 MPa stays below the flow stress and only the typical range speaks
    json patch = {{"strip", {{"flow_stress_MPa", 900}}},
                  {"tension", {{"back", {{"stress_MPa", 600}}}}}};
    api::canonicalise_scenario_patch(patch, "/scenario", errors);
    const core::Scenario scenario = api::scenario_from_patch(patch, "/scenario", errors);
    REQUIRE(errors.empty());
    const json warnings = api::typical_range_warnings(scenario, "/scenario");
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0]["pointer"] == "/scenario/tension/back/stress_MPa");
    CHECK(warnings[0]["likely"]["key"] == "force_kN");
    CHECK(warnings[0]["likely"]["unit"] == "kN");
    // 600 kN over 1.8 m × 1.6 mm
    CHECK(warnings[0]["likely"]["value"].get<double>() ==
          rollgap::test::approx(600e3 / (1.8 * 1.6e-3) / 1e6).epsilon(1e-14));
}

TEST_CASE(
    "plant units: a tension in kN that breaks a rule across fields is reported at the force, its "
    "bound in kN") {
    const auto refused = [](json patch) {
        CAPTURE(patch.dump());
        api::FieldErrors errors;
        api::canonicalise_scenario_patch(patch, "/scenario", errors);
        (void)api::scenario_from_patch(patch, "/scenario", errors);
        REQUIRE(errors.reported().size() == 1);
        return errors.reported().front();
    };
    // The default strip: 1.8 m wide, 1.6 mm in, 15 % reduction (1.36 mm out), σ = 380 MPa.
    const double back_area = 1.8 * 1.6e-3;
    const double front_area = 1.8 * 1.6e-3 * 0.85;
    // 1200 kN over the back cross-section is 416.7 MPa: inside the stress's own bound
    // [0, 3000) MPa, above the flow stress.
    const api::FieldError back = refused({{"tension", {{"back", {{"force_kN", 1200}}}}}});
    CHECK(back.pointer == "/scenario/tension/back/force_kN");
    CHECK(back.unit == "kN");
    REQUIRE(back.bound.has_value());
    CHECK(back.bound->starts_with("[0, "));
    CHECK(back.bound->ends_with(")"));
    // below the flow stress: σ · w · h in kN
    CHECK(std::stod(back.bound->substr(4)) ==
          rollgap::test::approx(380e6 * back_area / 1e3).epsilon(1e-12));
    CHECK(back.detail.find("flow stress") != std::string::npos);
    CHECK(back.detail.find("1200 kN") != std::string::npos);
    // The front over the exit thickness: 1000 kN is 408.5 MPa there (367.6 MPa over the entry's)
    const api::FieldError front = refused({{"tension", {{"front", {{"force_kN", 1000}}}}}});
    CHECK(front.pointer == "/scenario/tension/front/force_kN");
    REQUIRE(front.bound.has_value());
    CHECK(std::stod(front.bound->substr(4)) ==
          rollgap::test::approx(380e6 * front_area / 1e3).epsilon(1e-12));
    // The same rule on a stress given as a stress stays at the stress, in MPa.
    const api::FieldError stress = refused({{"tension", {{"back", {{"stress_MPa", 400}}}}}});
    CHECK(stress.pointer == "/scenario/tension/back/stress_MPa");
    CHECK(stress.unit == "MPa");
    // A ripple in kN that would slacken the strip: at the amplitude's force, bounded by the
    // mean's force (100 kN over the back cross-section).
    const api::FieldError ripple =
        refused({{"tension",
                  {{"back", {{"mode", "sinusoid"}, {"force_kN", 100}, {"amplitude_kN", 150}}}}}});
    CHECK(ripple.pointer == "/scenario/tension/back/amplitude_kN");
    CHECK(ripple.unit == "kN");
    REQUIRE(ripple.bound.has_value());
    CHECK(ripple.bound->starts_with("[0, "));
    CHECK(std::stod(ripple.bound->substr(4)) == rollgap::test::approx(100.0).epsilon(1e-12));
}

TEST_CASE("plant units: a mill's tensions in kN over the strip's cross-section in each span") {
    // three stands, 2.0 → 1.6 → 1.3 → 1.1 mm, the mill's strip 1000 mm wide
    json patch = {{"entry_thickness_mm", 2.0},
                  {"exit_thickness_mm", {1.6, 1.3, 1.1}},
                  {"strip", {{"width_mm", 1000}}},
                  {"spans", {{"length_m", {5, 5}}, {"tension_kN", {120, 100}}}},
                  {"entry", {{"tension_kN", 40}}},
                  {"exit", {{"tension_kN", 60}}},
                  {"stands", {json::object(), json::object(), json::object()}}};
    api::FieldErrors errors;
    api::canonicalise_tandem_patch(patch, "/tandem", errors);
    const core::Mill mill = api::mill_from_patch(patch, "/tandem", errors);
    std::string reported;
    for (const auto& e : errors.reported()) reported += e.pointer + ": " + e.detail + "\n";
    INFO(reported);
    REQUIRE(errors.empty());
    // entry: the width × the entry thickness; span i and the exit: × stand i's exit thickness
    CHECK(mill.entry_tension == rollgap::test::approx(40e3 / (1.0 * 2.0e-3)).epsilon(1e-14));
    REQUIRE(mill.interstand_tension.size() == 2);
    CHECK(mill.interstand_tension[0] ==
          rollgap::test::approx(120e3 / (1.0 * 1.6e-3)).epsilon(1e-14));
    CHECK(mill.interstand_tension[1] ==
          rollgap::test::approx(100e3 / (1.0 * 1.3e-3)).epsilon(1e-14));
    CHECK(mill.exit_tension == rollgap::test::approx(60e3 / (1.0 * 1.1e-3)).epsilon(1e-14));
    // each stand runs with the tensions of its spans
    CHECK(mill.stands[1].tensions.back.stress == mill.interstand_tension[0]);
    // the echo is in MPa
    const json echoed = api::resolved_tandem_json(mill);
    CHECK_FALSE(echoed["spans"].contains("tension_kN"));
    CHECK(echoed["spans"]["tension_MPa"][0].get<double>() ==
          rollgap::test::approx(75.0).epsilon(1e-14));

    // A list of the wrong length and a force beyond the bound are reported where they were sent.
    json wrong = {{"entry_thickness_mm", 2.0},
                  {"exit_thickness_mm", {1.6, 1.3, 1.1}},
                  {"spans", {{"length_m", {5, 5}}, {"tension_kN", {120}}}},
                  {"exit", {{"tension_kN", 1e6}}},
                  {"stands", {json::object(), json::object(), json::object()}}};
    api::FieldErrors refused;
    api::canonicalise_tandem_patch(wrong, "/tandem", refused);
    (void)api::mill_from_patch(wrong, "/tandem", refused);
    CHECK(put::error_pointers(refused) ==
          std::set<std::string>{"/tandem/spans/tension_kN", "/tandem/exit/tension_kN"});
    for (const auto& e : refused.reported()) CHECK(e.unit == "kN");
}

TEST_CASE("field tables: every field has a name for labels, unique within its table") {
    std::set<std::string> scenario_names;
    for (const api::ScenarioField& field : api::scenario_fields()) {
        CAPTURE(field.path);
        CHECK_FALSE(field.name.empty());
        CHECK(scenario_names.insert(field.name).second);
        // a name, not a pointer or a JSON key
        CHECK(field.name.find('/') == std::string::npos);
        CHECK(field.name.find('_') == std::string::npos);
    }
    std::set<std::string> tandem_names;
    for (const api::TandemField& field : api::tandem_fields()) {
        CAPTURE(field.path);
        CHECK_FALSE(field.name.empty());
        CHECK(tandem_names.insert(field.name).second);
        CHECK(field.name.find('_') == std::string::npos);
    }
}
