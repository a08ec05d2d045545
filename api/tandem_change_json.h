#pragma once
// What to change to run a tandem mill faster (docs/model.md §13.6): the numbers of the tandem
// document a plant can set, named by their JSON pointers relative to the document, with their
// typical steps (options.changes of tandem_speed_limit), and the answer's `what_to_change`.
//
// A change field is one of
//   /stands/{i}/<scenario field>          stand i's own number (its viscosity, roughness, roll
//                                          radius, damping ...), not one the mill gives a stand
//   /stand_defaults/<scenario field>       the same number of every stand at once (one emulsion
//                                          system feeding the whole mill)
//   /<mill number>                         /entry/tension_MPa, /exit/tension_MPa,
//                                          /entry_thickness_mm, /strip/width_mm, ...
//   /<mill list>/{k}                       /spans/tension_MPa/1, /exit_thickness_mm/2, ...
// never the mill speed (the answer) nor a count.

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/interval.h"
#include "api/result_table.h"
#include "api/units.h"
#include "core/mill/mill.h"
#include "core/mill/mill_limit_sensitivity.h"

namespace rollgap::api {

inline constexpr int max_mill_change_fields = 30;

struct MillChangeField {
    std::string path;  // relative to the tandem document
    Unit unit = units::one;
    Interval range;     // the field's bounds, in `unit`
    double step = 0.0;  // SI
    // the value (SI); nullopt for /stand_defaults/ when the stands' values differ
    std::function<std::optional<double>(const core::Mill&)> value;
    // every value the change moves (one, or every stand's), SI: for the bounds' check
    std::function<std::vector<double>(const core::Mill&)> values;
    std::function<void(core::Mill&, double)> shift;  // adds delta (SI)
};

// The field at `path` of a mill of `stands` stands (0: the count is not known, any stand index
// up to the largest mill is taken); nullopt with `why` (and the accepted form in `expected`).
std::optional<MillChangeField> find_mill_change_field(std::string_view path, int stands,
                                                      std::string& why, std::string& expected);

// Why a stand's scenario field is not the stand's own to change or fit in a mill: the mill gives
// it (its thicknesses, tensions, width, E, roll speed), with the mill's pointer that sets it
// ("/exit_thickness_mm/2" for stand 2's reduction when stand and stands are known); "" when the
// stand owns it.
std::string mill_given_field_message(std::string_view stand_path, int stand, int stands);

// What a plant sets between coils, with a step it would take: every tension (5 MPa), each
// intermediate thickness (0.02 mm; the product's is not a change), each stand's viscosity
// (0.1 mPa.s), work-roll roughness (0.1 um) and roll radius (10 mm).
std::vector<MillChangeField> default_mill_change_fields(int stands);

// options.changes: [{field, step}], at most max_mill_change_fields, none twice, every violation
// at once. `stands` as find_mill_change_field.
void read_mill_changes(const nlohmann::json& list, const std::string& pointer, int stands,
                       std::vector<MillChangeField>& out, FieldErrors& errors);
nlohmann::json mill_changes_json(const std::vector<MillChangeField>& changes);

struct MillWhatToChange {
    std::vector<MillChangeField> changes;
    core::MillBindingSensitivity sensitivity;
    core::Mill mill;  // the values the changes start from
    double chatter_margin = 0.0;
};

nlohmann::json mill_what_to_change_json(const MillWhatToChange& what);
std::vector<ResultSchema>
mill_what_to_change_schemas();  // TandemSpeedLimitChange, TandemWhatToChange

}  // namespace rollgap::api
