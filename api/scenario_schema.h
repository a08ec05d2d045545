#pragma once
// The scenario schema as one table: every field of core::Scenario is one row with its JSON
// path, unit, bounds and accessor. Reading, writing, the default document, unknown-field
// detection and sweeps over "any numeric field" all come from this table, so a field
// cannot be readable but not echoed, or bounded in one place and not another.

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "api/interval.h"
#include "api/units.h"
#include "core/scenario.h"

namespace rollgap::api {

enum class FieldKind { number, integer, boolean, choice };

struct ScenarioField {
    std::string path;  // JSON pointer relative to the scenario: "/strip/entry_thickness_mm"
    FieldKind kind = FieldKind::number;

    // number and integer fields; bounds are in `unit`, i.e. as the client writes them
    Unit unit = units::one;
    Interval range{0.0, 0.0};
    bool even = false;  // integer fields that must be even

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

}  // namespace rollgap::api
