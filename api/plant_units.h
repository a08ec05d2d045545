#pragma once
// Plant units (docs/http-api.md, "Plant units"): a member of the scenario or the tandem document
// may be given in a unit plants use instead of its canonical one — a speed in m/min or mm/s, a
// viscosity in mPa·s, a roll's diameter instead of its radius, masses in kg, stiffnesses in
// kN/mm, dampings in kN·s/m — under the key that names that unit (`speed_m_per_min`,
// `diameter_mm`, `masses_kg`). One table holds every such alternate; a patch is rewritten to
// its canonical keys before it is merged with anything (each layer on its own: a base, a batch
// item, a stand), converted exactly, so the echo is always canonical. Never a guess from a
// value's magnitude: the key says the unit.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/interval.h"
#include "core/mill/mill.h"
#include "core/scenario.h"

namespace rollgap::api {

struct AlternateUnit {
    // A member name's suffix ("_m_per_s") or, with whole_name, the name itself ("radius_mm",
    // "masses_t", a group).
    std::string_view canonical;
    std::string_view alternate;  // what replaces it: "_m_per_min", "diameter_mm", "masses_kg"
    std::string_view unit;       // the alternate's unit (UCUM): "m/min", "mm", "kg"
    // canonical value = alternate value ÷ divisor × 10^decimal_shift; a power of ten shifts the
    // value's shortest decimal form (api/units.h to_si), so 0.55 mPa·s is exactly the double
    // of 0.00055 Pa·s; a divisor (60, 2) is one correctly rounded division.
    double divisor = 1.0;
    int decimal_shift = 0;
    bool whole_name = false;
    std::string_view note;  // how it converts, for the documentation: "÷ 60"
    // A force over the strip's cross-section on that side (a tension in kN): converted only
    // when the scenario is read, with its width and thickness, which another layer may give
    // (resolve_tension_forces). The rewrite keeps the key, and each layer that gives one form
    // clears the other (adds it as null), so a later layer's form wins a merge either way.
    bool per_cross_section = false;
};

std::span<const AlternateUnit> alternate_units();

// The alternates of a canonical member name: (alternate key, its row), in table order.
std::vector<std::pair<std::string, const AlternateUnit*>> alternates_of(std::string_view member);

// The canonical value of `value` given in `unit`.
double canonical_value(double value, const AlternateUnit& unit);

// Rewrites the alternate members of a scenario merge patch (at `pointer`, e.g. "/scenario") to
// their canonical keys, recursively through its groups. null stays null (the default); a group
// alternate (`masses_kg`) converts each member. A member given in two forms in one object, or
// an alternate whose value is not a number (or a group's not an object), is an error at its
// pointer; every violation is reported.
void canonicalise_scenario_patch(nlohmann::json& patch, const std::string& pointer,
                                 FieldErrors& errors);

// The same for a tandem document (or merge patch): its own members, the shared stand defaults
// and each stand's patch.
void canonicalise_tandem_patch(nlohmann::json& patch, const std::string& pointer,
                               FieldErrors& errors);

// Every scenario and tandem document under `node` (at `pointer`), wherever it sits: "scenario"
// and "tandem" members at any depth (a request's own, a batch's shared ones and its items', a
// calibration's observations'), pointers naming where each is.
void canonicalise_request_units(nlohmann::json& node, const std::string& pointer,
                                FieldErrors& errors);

// The members that stand for some of `members` but are converted only when the document is
// read (AlternateUnit::per_cross_section): for the members of "/tension/back", {"force_kN",
// "amplitude_kN"}; of the mill's "/spans", {"tension_kN"}; else none.
std::vector<std::string> deferred_alternates(std::span<const std::string_view> members);

// The strip's cross-section on the side of tension group `group` ("/tension/back": entry
// thickness × width; "/tension/front": exit thickness × width), in m²; nothing for another group.
std::optional<double> tension_cross_section_m2(const core::Scenario& scenario,
                                               std::string_view group);

// A tension given as a force: `force` (JSON, in kN) over `area_m2` as a stress in the unit of
// `range` (MPa), when it is a finite number whose stress lies in `range`; else an error at `at`
// (not a number, or outside the range with the bound in kN over this cross-section; `section`
// names it: "width × entry thickness"). One rule for a stand's sides and a mill's spans.
std::optional<double> stress_of_force(const nlohmann::json& force, const std::string& at,
                                      double area_m2, const Interval& range,
                                      std::string_view section, FieldErrors& errors);

// A field the client gave in another unit by another member (a tension as a force): a rule
// that involves the canonical field (scenario_consistency.h) reports at the member given, with
// its bound in that unit (bound × per_canonical).
struct GivenAs {
    std::string canonical;  // "/tension/back/stress_MPa"
    std::string given;      // "/tension/back/force_kN"
    double per_canonical;   // given unit per canonical unit: kN per MPa is the area in m² × 1000
    std::string_view unit;  // "kN"
    double value;           // as given, in `unit`
};

// Tensions given as forces (`/tension/{back,front}/force_kN`, `amplitude_kN` in the merged
// scenario document at `pointer`): the stresses over that side's cross-section, written into
// `scenario` once its strip has been read (a force whose stress leaves the stress's bounds is
// an error at the force's pointer, with the bound in kN). Returns the forces converted, for
// the cross-field rules to name.
std::vector<GivenAs> resolve_tension_forces(const nlohmann::json& document,
                                            const std::string& pointer, core::Scenario& scenario,
                                            FieldErrors& errors);

// A table column in its plant unit (CSV with units=plant, docs/http-api.md "Plant units"): a
// column whose name ends in a canonical unit suffix that has a plant unit (`_m_per_s` →
// `_m_per_min`, `_Pa_s` → `_mPa_s`; the first row of that suffix in the table), renamed, and
// the row that converts its values; nothing for every other column, which stays as it is.
struct PlantColumn {
    std::string name;
    const AlternateUnit* unit = nullptr;
};
std::optional<PlantColumn> plant_column(std::string_view column);

// The value in the plant unit of a canonical value: the inverse of canonical_value (× 60 for
// m/min; a power of ten shifts the decimal, so 0.00055 Pa·s is exactly 0.55 mPa·s).
double plant_value(double canonical, const AlternateUnit& unit);

// A value that lies outside `target` in its field's unit but inside it read in one of the
// field's (or its group's) plant units: the key that gives it in that unit, the unit, the value
// it would then be, and a sentence ("if 900 m/min was meant, that is 15 m/s: send it as
// speed_m_per_min"). `path`: the field's path in its table ("/rolls/speed_m_per_s").
struct UnitSlip {
    std::string key;
    const AlternateUnit* unit = nullptr;
    double meant = 0.0;
    std::string text;
};
// `cross_section_m2`: the strip's cross-section on the field's side, for the forces of
// per_cross_section rows (without it those are not considered).
std::optional<UnitSlip> likely_unit_slip(std::string_view path, std::string_view canonical_unit,
                                         const Interval& target, double value,
                                         std::optional<double> cross_section_m2 = std::nullopt);

// Values outside their field's typical plant range (ScenarioField::typical): accepted, and
// answered with one warning each, {pointer, detail, typical, unit} and, when reading the value
// in one of the field's plant units would put it inside the range, `likely`: {key, unit,
// value} — 90 in speed_m_per_s is likely 90 m/min, speed_m_per_min, 1.5 m/s. An array, empty
// when every value is typical.
nlohmann::json typical_range_warnings(const core::Scenario& scenario, const std::string& pointer);
// The same for a mill: its speed and each stand's own fields (not those the mill gives a stand)
// at /tandem/stands/<i>/....
nlohmann::json typical_range_warnings(const core::Mill& mill, const std::string& pointer);

}  // namespace rollgap::api
