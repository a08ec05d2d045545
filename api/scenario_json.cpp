#include "api/scenario_json.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "api/plant_units.h"
#include "api/scenario_consistency.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

// Quantities a client may reasonably try to set that are derived, not inputs.
std::optional<std::string> derived_quantity_hint(std::string_view group, std::string_view name) {
    if (group == "/strip" && name.starts_with("exit_thickness")) {
        return "the exit thickness is entry_thickness_mm × (1 − reduction); set 'reduction'";
    }
    if (group == "/mill/stiffness_GN_per_m" && name == "k4") {
        return "k4 is the strip's stiffness, derived from the roll-bite model (docs/model.md §5), "
               "not an input";
    }
    if (group == "/mill/damping_MN_s_per_m" && name.starts_with("rayleigh")) {
        return "Rayleigh damping is set in /mill/rayleigh";
    }
    return std::nullopt;
}

void read_field(const ScenarioField& field, const nlohmann::json& value, const std::string& pointer,
                core::Scenario& scenario, FieldErrors& errors) {
    switch (field.kind) {
        case FieldKind::number:
            // Out of bounds, but a plant unit would fit: say which (plant_units.h).
            if (value.is_number() && std::isfinite(value.get<double>()) &&
                !field.range.contains(value.get<double>())) {
                const double number = value.get<double>();
                if (const auto slip = likely_unit_slip(
                        field.path, field.unit.code, field.typical.value_or(field.range), number)) {
                    errors.add({pointer,
                                concat(format_number(number), " ", field.unit.code, " is outside ",
                                       field.range.text(), " ", field.unit.code, "; ", slip->text),
                                field.range.text(), std::string(field.unit.code)});
                    return;
                }
            }
            if (const auto number = read_number(value, pointer, field.range, field.unit, errors)) {
                field.number(scenario) = to_si(*number, field.unit);
            }
            return;
        case FieldKind::integer:
            if (const auto integer =
                    read_integer(value, pointer, field.range, field.even, errors)) {
                field.integer(scenario) = static_cast<int>(*integer);  // within range, fits
            }
            return;
        case FieldKind::boolean:
            if (const auto flag = read_boolean(value, pointer, errors))
                field.flag(scenario) = *flag;
            return;
        case FieldKind::choice:
            if (const auto choice = read_choice(value, pointer, field.choices, errors)) {
                field.write_choice(scenario, *choice);
            }
            return;
    }
}

// Schema paths are pointers already: schema names contain neither '/' nor '~'.
void read_group(const std::string& group, const nlohmann::json& node,
                const std::string& base_pointer, core::Scenario& scenario, FieldErrors& errors) {
    const std::string pointer = base_pointer + group;
    if (!require_object(node, pointer, errors)) return;
    const auto members = scenario_group_members(group);
    // A tension side also knows its forces in kN (plant_units.h), read after the strip.
    const std::vector<std::string> deferred = deferred_alternates(members);
    std::vector<std::string_view> known(members.begin(), members.end());
    known.insert(known.end(), deferred.begin(), deferred.end());
    reject_unknown_fields(node, pointer, known, errors, [&group](std::string_view name) {
        return derived_quantity_hint(group, name);
    });
    for (const std::string_view member : members) {
        const auto value = node.find(std::string(member));
        if (value == node.end()) continue;  // missing: the default stays
        const std::string path = concat(group, "/", member);
        if (is_scenario_group(path)) {
            read_group(path, *value, base_pointer, scenario, errors);
        } else if (const ScenarioField* field = find_scenario_field(path)) {
            read_field(*field, *value, base_pointer + path, scenario, errors);
        } else {
            throw std::logic_error(concat("scenario schema member without a field: ", path));
        }
    }
}

}  // namespace

nlohmann::json resolved_scenario_json(const core::Scenario& scenario) {
    core::Scenario readable = scenario;  // the accessors hand out references
    nlohmann::json document = nlohmann::json::object();
    for (const ScenarioField& field : scenario_fields()) {
        nlohmann::json& slot = document[nlohmann::json::json_pointer(field.path)];
        switch (field.kind) {
            case FieldKind::number: slot = from_si(field.number(readable), field.unit); break;
            case FieldKind::integer: slot = field.integer(readable); break;
            case FieldKind::boolean: slot = field.flag(readable); break;
            case FieldKind::choice: slot = std::string(field.read_choice(readable)); break;
        }
    }
    return document;
}

nlohmann::json default_scenario_json() {
    static const nlohmann::json defaults = resolved_scenario_json(core::Scenario{});
    return defaults;
}

core::Scenario scenario_from_json(const nlohmann::json& document, const std::string& pointer,
                                  FieldErrors& errors) {
    core::Scenario scenario{};
    read_group("", document, pointer, scenario, errors);
    // Tensions given as forces, over the strip's cross-section as read (docs/http-api.md,
    // "Plant units").
    const std::vector<GivenAs> forces = resolve_tension_forces(document, pointer, scenario, errors);
    // Cross-field rules on a document that is not even an object would only add noise; a rule
    // on a tension given as a force names the force.
    if (document.is_object()) check_scenario_consistency(scenario, pointer, errors, forces);
    return scenario;
}

core::Scenario scenario_from_patch(const nlohmann::json& patch, const std::string& pointer,
                                   FieldErrors& errors) {
    // JSON Merge Patch (RFC 7396): the client sends only what differs; null removes a member,
    // which here means back to its default. Recursive in the depth of `patch`: callers bound
    // the depth of client JSON first (json_text.h).
    nlohmann::json scenario = default_scenario_json();
    scenario.merge_patch(patch);
    return scenario_from_json(scenario, pointer, errors);
}

}  // namespace rollgap::api
