#include "api/plant_units.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>

#include "api/json_pointer.h"
#include "api/scenario_schema.h"
#include "api/tandem_schema.h"
#include "api/text.h"
#include "api/units.h"

namespace rollgap::api {
namespace plant_units_detail {

using nlohmann::json;

// The table: one row per alternate (docs/http-api.md lists it).
constexpr std::array<AlternateUnit, 10> table{{
    {"_m_per_s", "_m_per_min", "m/min", 60.0, 0, false, "÷ 60"},
    {"_m_per_s", "_mm_per_s", "mm/s", 1.0, -3, false, "÷ 1000"},
    {"_Pa_s", "_mPa_s", "mPa.s", 1.0, -3, false, "÷ 1000"},
    {"radius_mm", "diameter_mm", "mm", 2.0, 0, true, "÷ 2: the radius is half the diameter"},
    {"masses_t", "masses_kg", "kg", 1.0, -3, true, "÷ 1000"},
    {"stiffness_GN_per_m", "stiffness_kN_per_mm", "kN/mm", 1.0, -3, true, "÷ 1000"},
    {"damping_MN_s_per_m", "damping_kN_s_per_m", "kN.s/m", 1.0, -3, true, "÷ 1000"},
    // A tension as the force the bridle or the stand pulls with, over the strip's cross-section
    // on that side (docs/http-api.md, "Plant units").
    {"stress_MPa", "force_kN", "kN", 1.0, 0, true,
     "÷ the strip's cross-section on that side (width × entry thickness for back, × exit "
     "thickness for front), which may come from another layer",
     true},
    {"amplitude_MPa", "amplitude_kN", "kN", 1.0, 0, true,
     "÷ the strip's cross-section on that side, as force_kN", true},
    // The mill's entry, interstand and exit tensions: over the strip's cross-section in that
    // span (docs/http-api.md, "Plant units").
    {"tension_MPa", "tension_kN", "kN", 1.0, 0, true,
     "÷ the strip's cross-section in that span (the mill's width × the entry thickness for the "
     "entry span, × the upstream stand's exit thickness for an interstand or the exit span)",
     true},
}};

// What a walker needs of a document's schema: its groups, their members, its numeric leaves.
struct Schema {
    std::function<bool(std::string_view)> is_group;
    std::function<std::span<const std::string_view>(std::string_view)> members;
};

const Schema& scenario_schema() {
    static const Schema schema{[](std::string_view path) { return is_scenario_group(path); },
                               [](std::string_view path) { return scenario_group_members(path); }};
    return schema;
}

const Schema& tandem_schema() {
    static const Schema schema{[](std::string_view path) { return is_tandem_group(path); },
                               [](std::string_view path) { return tandem_group_members(path); }};
    return schema;
}

// A number (or a list of numbers) in `unit`, converted; nothing for anything else.
std::optional<json> converted(const json& value, const AlternateUnit& unit) {
    if (value.is_null()) return json(nullptr);
    if (value.is_number()) return json(canonical_value(value.get<double>(), unit));
    if (value.is_array()) {
        json list = json::array();
        for (const json& element : value) {
            if (!element.is_number()) return std::nullopt;
            list.push_back(canonical_value(element.get<double>(), unit));
        }
        return list;
    }
    return std::nullopt;
}

void walk(json& object, const std::string& schema_path, const std::string& pointer,
          const Schema& schema, FieldErrors& errors);

// Member `alternate` of `object` stands for the canonical `member`: rewritten in place.
void rewrite(json& object, const std::string& member, const std::string& alternate,
             const AlternateUnit& unit, const std::string& schema_path, const std::string& pointer,
             const Schema& schema, FieldErrors& errors) {
    const std::string at = concat(pointer, "/", escape_pointer_token(alternate));
    json value = std::move(object[alternate]);
    object.erase(alternate);
    const std::string child = concat(schema_path, "/", member);
    if (schema.is_group(child)) {
        // a group in another unit: each member of it (its own keys are canonical)
        if (!value.is_object() && !value.is_null()) {
            errors.add({at, concat("must be an object of values in ", unit.unit, ", like ", member),
                        std::nullopt, std::string(unit.unit)});
            return;
        }
        if (value.is_object()) {
            for (auto& [name, element] : value.items()) {
                if (const auto number = converted(element, unit); number && !element.is_array()) {
                    element = *number;
                } else {
                    errors.add({concat(at, "/", escape_pointer_token(name)),
                                concat("must be a number in ", unit.unit), std::nullopt,
                                std::string(unit.unit)});
                }
            }
        }
        object[member] = std::move(value);
        return;
    }
    const auto number = converted(value, unit);
    if (!number) {
        errors.add({at,
                    concat("must be a number in ", unit.unit, " (or null), converted to ", member),
                    std::nullopt, std::string(unit.unit)});
        return;
    }
    object[member] = *number;
}

void walk(json& object, const std::string& schema_path, const std::string& pointer,
          const Schema& schema, FieldErrors& errors) {
    if (!object.is_object()) return;
    // Each canonical member of this group and the alternate keys given for it: one form is
    // rewritten, two or more are refused at each of them (which one was meant is not guessed).
    for (const std::string_view member : schema.members(schema_path)) {
        // A null per-cross-section form only clears an earlier layer's: no form of its own.
        const bool canonical_given = object.contains(member) && !object[member].is_null();
        std::vector<std::pair<std::string, const AlternateUnit*>> given;
        for (auto& candidate : alternates_of(member)) {
            const auto found = object.find(candidate.first);
            if (found == object.end()) continue;
            if (candidate.second->per_cross_section && found->is_null()) continue;
            given.push_back(std::move(candidate));
        }
        if (given.empty()) {
            // The canonical form given: it clears a force an earlier layer gave.
            if (canonical_given) {
                for (const auto& [alternate, unit] : alternates_of(member))
                    if (unit->per_cross_section) object[alternate] = nullptr;
            }
            continue;
        }
        if (given.size() == 1 && !canonical_given && given[0].second->per_cross_section) {
            // Kept for the reader (resolve_tension_forces); it clears an earlier stress.
            const json& force = object[given[0].first];
            const bool numbers =
                force.is_number() ||
                (force.is_array() && std::all_of(force.begin(), force.end(),
                                                 [](const json& v) { return v.is_number(); }));
            if (!numbers) {
                errors.add({concat(pointer, "/", escape_pointer_token(given[0].first)),
                            concat("must be ",
                                   schema_path == "/spans" ? "an array of numbers, one per span,"
                                                           : "a number",
                                   " in ", given[0].second->unit, " (or null)"),
                            std::nullopt, std::string(given[0].second->unit)});
                object.erase(given[0].first);
                continue;
            }
            object[std::string(member)] = nullptr;
            continue;
        }
        if (given.size() == 1 && !object.contains(member)) {
            rewrite(object, std::string(member), given[0].first, *given[0].second, schema_path,
                    pointer, schema, errors);
            continue;
        }
        std::string names = object.contains(member) ? std::string(member) : std::string();
        for (const auto& [alternate, unit] : given)
            names += concat(names.empty() ? "" : ", ", alternate);
        const std::string detail =
            concat("one value in one unit: give one of ", names, ", not several");
        if (object.contains(member))
            errors.add({concat(pointer, "/", escape_pointer_token(member)), detail, std::nullopt,
                        std::nullopt});
        for (const auto& [alternate, unit] : given) {
            errors.add({concat(pointer, "/", escape_pointer_token(alternate)), detail, std::nullopt,
                        std::nullopt});
            object.erase(alternate);  // reported once, here, not again as an unknown member
        }
    }
    for (auto& [name, value] : object.items()) {
        const std::string child = concat(schema_path, "/", name);
        if (schema.is_group(child))
            walk(value, child, concat(pointer, "/", escape_pointer_token(name)), schema, errors);
    }
}

void walk_request(json& node, const std::string& pointer, FieldErrors& errors) {
    if (node.is_object()) {
        for (auto& [name, value] : node.items()) {
            const std::string at = concat(pointer, "/", escape_pointer_token(name));
            if (name == "scenario" && value.is_object()) {
                canonicalise_scenario_patch(value, at, errors);
            } else if (name == "tandem" && value.is_object()) {
                canonicalise_tandem_patch(value, at, errors);
            } else {
                walk_request(value, at, errors);
            }
        }
    } else if (node.is_array()) {
        for (std::size_t i = 0; i < node.size(); ++i)
            walk_request(node[i], concat(pointer, "/", std::to_string(i)), errors);
    }
}

// One value against its typical range; nothing when typical.
std::optional<json> typical_warning(double value, const ScenarioField& field,
                                    const std::string& pointer,
                                    std::optional<double> cross_section_m2 = std::nullopt) {
    if (!field.typical || field.typical->contains(value)) return std::nullopt;
    const Interval& typical = *field.typical;
    const std::string unit(field.unit.code);
    json warning = {
        {"pointer", pointer},
        {"typical", typical.text()},
        {"unit", unit},
    };
    std::string detail =
        concat(format_number(value), " ", unit, " is ", value < typical.min ? "below" : "above",
               " the typical ", typical.text(), " ", unit, " of a cold mill; it is used as given");
    // Which plant unit would make it typical.
    if (const auto slip = likely_unit_slip(field.path, unit, typical, value, cross_section_m2)) {
        detail += concat("; ", slip->text);
        warning["likely"] = {
            {"key", slip->key}, {"unit", slip->unit->unit}, {"value", slip->meant}};
    }
    warning["detail"] = std::move(detail);
    return warning;
}

void add_scenario_warnings(const core::Scenario& scenario, const std::string& pointer,
                           const std::function<bool(const ScenarioField&)>& skip, json& out) {
    core::Scenario readable = scenario;  // the accessors take a reference; this only reads
    for (const ScenarioField& field : scenario_fields()) {
        if (!field.typical || field.kind != FieldKind::number || skip(field)) continue;
        const double value = from_si(field.number(readable), field.unit);
        const std::string_view group =
            std::string_view(field.path).substr(0, field.path.rfind('/'));
        if (auto warning = typical_warning(value, field, concat(pointer, field.path),
                                           tension_cross_section_m2(scenario, group)))
            out.push_back(std::move(*warning));
    }
}

}  // namespace plant_units_detail

std::optional<UnitSlip> likely_unit_slip(std::string_view path, std::string_view canonical_unit,
                                         const Interval& target, double value,
                                         std::optional<double> cross_section_m2) {
    const std::string_view member = path.substr(path.rfind('/') + 1);
    const std::string_view group = path.substr(0, path.rfind('/'));
    std::vector<std::pair<std::string, const AlternateUnit*>> candidates = alternates_of(member);
    for (auto& [key, row] : alternates_of(group.substr(group.rfind('/') + 1)))
        candidates.emplace_back(concat(key, "/", member), row);
    for (const auto& [key, row] : candidates) {
        if (row->per_cross_section && !cross_section_m2) continue;
        // kN over m² is kPa: ÷ 1000 for MPa
        const double meant = row->per_cross_section ? value / *cross_section_m2 / 1000.0
                                                    : canonical_value(value, *row);
        if (!target.contains(meant)) continue;
        return UnitSlip{key, row, meant,
                        concat("if ", format_number(value), " ", row->unit, " was meant, that is ",
                               format_number(meant), " ", canonical_unit, ": send it as ", key)};
    }
    return std::nullopt;
}

nlohmann::json typical_range_warnings(const core::Scenario& scenario, const std::string& pointer) {
    nlohmann::json out = nlohmann::json::array();
    plant_units_detail::add_scenario_warnings(
        scenario, pointer, [](const ScenarioField&) { return false; }, out);
    return out;
}

nlohmann::json typical_range_warnings(const core::Mill& mill, const std::string& pointer) {
    nlohmann::json out = nlohmann::json::array();
    // The mill's speed is its last stand's roll speed: judged as a roll speed.
    if (const ScenarioField* speed = find_scenario_field("/rolls/speed_m_per_s")) {
        if (auto warning = plant_units_detail::typical_warning(
                from_si(mill.speed, speed->unit), *speed, concat(pointer, "/speed_m_per_s")))
            out.push_back(std::move(*warning));
    }
    const int stands = static_cast<int>(mill.stands.size());
    for (int i = 0; i < stands; ++i) {
        plant_units_detail::add_scenario_warnings(
            mill.stands[static_cast<std::size_t>(i)],
            concat(pointer, "/", stands_member, "/", std::to_string(i)),
            [&](const ScenarioField& field) {
                return !tandem_pointer_of_stand_field(field.path, i, stands).empty();
            },
            out);
    }
    return out;
}

std::span<const AlternateUnit> alternate_units() { return plant_units_detail::table; }

std::vector<std::string> deferred_alternates(std::span<const std::string_view> members) {
    std::vector<std::string> found;
    for (const std::string_view member : members)
        for (const auto& [alternate, unit] : alternates_of(member))
            if (unit->per_cross_section) found.push_back(alternate);
    return found;
}

std::optional<double> tension_cross_section_m2(const core::Scenario& scenario,
                                               std::string_view group) {
    if (group == "/tension/back") return scenario.strip.width * scenario.strip.entry_thickness;
    if (group == "/tension/front") return scenario.strip.width * core::exit_thickness(scenario);
    return std::nullopt;
}

std::optional<double> stress_of_force(const nlohmann::json& force, const std::string& at,
                                      double area_m2, const Interval& range,
                                      std::string_view section, FieldErrors& errors) {
    if (!force.is_number()) {
        errors.add({at, "must be a number in kN (or null)", std::nullopt, "kN"});
        return std::nullopt;
    }
    const double force_kn = force.get<double>();
    const double stress = force_kn / area_m2 / 1000.0;  // kN/m² is kPa: ÷ 1000 for MPa
    if (std::isfinite(force_kn) && range.contains(stress)) return stress;
    const Interval in_kilonewton{range.min * area_m2 * 1000.0, range.max * area_m2 * 1000.0,
                                 range.min_open, range.max_open};
    errors.add({at,
                concat(format_number(force_kn), " kN over the strip's ",
                       format_number(area_m2 * 1e6), " mm² (", section, ") is ",
                       format_number(stress), " MPa, outside ", range.text(), " MPa"),
                in_kilonewton.text(), "kN"});
    return std::nullopt;
}

std::vector<GivenAs> resolve_tension_forces(const nlohmann::json& document,
                                            const std::string& pointer, core::Scenario& scenario,
                                            FieldErrors& errors) {
    std::vector<GivenAs> converted;
    if (!document.is_object()) return converted;
    for (const std::string_view group :
         {std::string_view("/tension/back"), std::string_view("/tension/front")}) {
        const nlohmann::json::json_pointer at{std::string(group)};
        if (!document.contains(at) || !document.at(at).is_object()) continue;
        const nlohmann::json& side = document.at(at);
        for (const std::string_view member : scenario_group_members(group)) {
            for (const auto& [alternate, unit] : alternates_of(member)) {
                if (!unit->per_cross_section) continue;
                const auto given = side.find(alternate);
                if (given == side.end() || given->is_null()) continue;
                const std::string where = concat(pointer, group, "/", alternate);
                if (errors.has_error_at_or_below(where)) continue;
                // Only over a strip that was read as given: else its own errors say why.
                if (errors.has_error_at_or_below(concat(pointer, "/strip"))) continue;
                const ScenarioField* field = find_scenario_field(concat(group, "/", member));
                if (field == nullptr) continue;
                const double area = *tension_cross_section_m2(scenario, group);
                const auto stress = stress_of_force(
                    *given, where, area, field->range,
                    group == "/tension/back" ? "width × entry thickness" : "width × exit thickness",
                    errors);
                if (!stress) continue;
                field->number(scenario) = to_si(*stress, field->unit);
                converted.push_back({field->path, concat(group, "/", alternate), area * 1000.0,
                                     unit->unit, given->get<double>()});
            }
        }
    }
    return converted;
}

std::vector<std::pair<std::string, const AlternateUnit*>> alternates_of(std::string_view member) {
    std::vector<std::pair<std::string, const AlternateUnit*>> found;
    for (const AlternateUnit& unit : plant_units_detail::table) {
        if (unit.whole_name) {
            if (member == unit.canonical) found.emplace_back(std::string(unit.alternate), &unit);
        } else if (member.size() > unit.canonical.size() && member.ends_with(unit.canonical)) {
            found.emplace_back(
                concat(member.substr(0, member.size() - unit.canonical.size()), unit.alternate),
                &unit);
        }
    }
    return found;
}

std::optional<PlantColumn> plant_column(std::string_view column) {
    for (const AlternateUnit& unit : plant_units_detail::table) {
        if (unit.whole_name || unit.per_cross_section) continue;
        if (column.size() <= unit.canonical.size() || !column.ends_with(unit.canonical)) continue;
        return PlantColumn{
            concat(column.substr(0, column.size() - unit.canonical.size()), unit.alternate), &unit};
    }
    return std::nullopt;
}

double plant_value(double canonical, const AlternateUnit& unit) {
    double value = canonical;
    if (unit.decimal_shift != 0) value = from_si(value, Unit{unit.unit, unit.decimal_shift});
    if (unit.divisor != 1.0) value *= unit.divisor;
    return value;
}

double canonical_value(double value, const AlternateUnit& unit) {
    if (unit.divisor != 1.0) value /= unit.divisor;
    if (unit.decimal_shift != 0) value = to_si(value, Unit{unit.unit, unit.decimal_shift});
    return value;
}

void canonicalise_scenario_patch(nlohmann::json& patch, const std::string& pointer,
                                 FieldErrors& errors) {
    plant_units_detail::walk(patch, "", pointer, plant_units_detail::scenario_schema(), errors);
}

void canonicalise_tandem_patch(nlohmann::json& patch, const std::string& pointer,
                               FieldErrors& errors) {
    if (!patch.is_object()) return;
    plant_units_detail::walk(patch, "", pointer, plant_units_detail::tandem_schema(), errors);
    const std::string defaults(stand_defaults_member);
    if (patch.contains(defaults))
        canonicalise_scenario_patch(patch[defaults], concat(pointer, "/", defaults), errors);
    const std::string stands(stands_member);
    if (patch.contains(stands) && patch[stands].is_array()) {
        auto& list = patch[stands];
        for (std::size_t i = 0; i < list.size(); ++i)
            canonicalise_scenario_patch(
                list[i], concat(pointer, "/", stands, "/", std::to_string(i)), errors);
    }
}

void canonicalise_request_units(nlohmann::json& node, const std::string& pointer,
                                FieldErrors& errors) {
    plant_units_detail::walk_request(node, pointer, errors);
}

}  // namespace rollgap::api
