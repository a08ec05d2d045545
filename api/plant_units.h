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
std::optional<UnitSlip> likely_unit_slip(std::string_view path, std::string_view canonical_unit,
                                         const Interval& target, double value);

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
