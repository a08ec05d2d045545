#pragma once
// The scenario schema as one table: every field of core::Scenario is one row with its JSON
// path, unit, bounds, description and accessor. Reading, writing, the default document,
// unknown-field detection, sweeps over any numeric field, the OpenAPI schema and the field
// glossary (`rollgap scenario --explain`) all come from this table, so a field cannot be
// readable but not echoed, bounded in one place and not another, or undocumented.

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "api/interval.h"
#include "api/units.h"
#include "core/scenario.h"

namespace rollgap::api {

enum class FieldKind { number, integer, boolean, choice };

struct ScenarioField {
    std::string path;  // JSON pointer relative to the scenario: "/strip/entry_thickness_mm"
    FieldKind kind = FieldKind::number;

    // What the field is on the mill, for a plant engineer: the part or quantity, its symbol in
    // docs/model.md, typical values with their unit. One sentence or a few; carried into the
    // OpenAPI document, `rollgap scenario --explain` and problem details.
    std::string description;
    // Its name for a label or an axis title, in words a plant engineer uses ("Roll speed",
    // "Back tension"): the OpenAPI property's title; the workbench labels with it, never with
    // the pointer.
    std::string name;

    // number and integer fields; bounds are in `unit`, i.e. as the client writes them
    Unit unit = units::one;
    Interval range{0.0, 0.0};
    bool even = false;  // integer fields that must be even
    // The range a cold mill's value lies in (in `unit`), narrower than `range`: a value outside
    // it is accepted and answered with a warning naming the likely unit slip (plant_units.h).
    std::optional<Interval> typical;

    // choice fields: the allowed strings, in the order the documentation lists them
    std::vector<std::string_view> choices;

    // Exactly the accessor(s) matching `kind` are set. Numbers are SI inside core::Scenario.
    std::function<double&(core::Scenario&)> number;
    std::function<int&(core::Scenario&)> integer;
    std::function<bool&(core::Scenario&)> flag;
    std::function<std::string_view(const core::Scenario&)> read_choice;
    std::function<void(core::Scenario&, std::string_view)> write_choice;  // choice is valid
};

// All fields, grouped as in the JSON document.
const std::vector<ScenarioField>& scenario_fields();

// The field at `path`, or nullptr.
const ScenarioField* find_scenario_field(std::string_view path);

// Objects of the document ("" is the scenario itself, "/tension/back" a nested group) and the
// names of their members (fields and subgroups) in schema order. Empty for a non-group.
bool is_scenario_group(std::string_view path);
std::span<const std::string_view> scenario_group_members(std::string_view path);

// The field table under a prefix (DECISIONS R, the field lens): the same fields and groups,
// addressed by their full JSON pointer in a larger document, so that a plant document can read
// and validate one stand where it sits, e.g. under "/tandem/stands/3". Every pointer a lens hands
// out or takes carries the full path, array indices included, which is what problem details
// must name. The empty prefix is the scenario document itself.
class FieldLens {
public:
    FieldLens() = default;
    // `prefix` is an RFC 6901 pointer ("" or "/a/b/3"), escaped, without a trailing '/'.
    explicit FieldLens(std::string prefix) : prefix_(std::move(prefix)) {}

    // The lens one level further down: a member of an object or an element of an array.
    FieldLens member(std::string_view name) const;
    FieldLens element(std::size_t index) const;

    const std::string& prefix() const { return prefix_; }

    // prefix + a schema path ("/strip/reduction", or "" for the scenario itself)
    std::string pointer(std::string_view schema_path) const;

    // The schema path of a full pointer under this lens ("" for the prefix itself); nullopt for
    // a pointer outside it ("/tandem/stands/30/..." is not under "/tandem/stands/3").
    std::optional<std::string_view> schema_path(std::string_view full_pointer) const;

    // find_scenario_field, is_scenario_group and scenario_group_members by full pointer.
    const ScenarioField* find_field(std::string_view full_pointer) const;
    bool is_group(std::string_view full_pointer) const;
    std::span<const std::string_view> group_members(std::string_view full_pointer) const;

    // Every field of the table, by its full pointer, in schema order.
    std::vector<std::string> field_pointers() const;

private:
    std::string prefix_;
};

}  // namespace rollgap::api
