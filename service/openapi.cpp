#include "service/openapi.h"

#include <array>
#include <string_view>

#include "api/field_errors.h"
#include "api/problem.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/text.h"
#include "api/units.h"
#include "core/scenario.h"
#include "service/analyses.h"
#include "service/analysis.h"
#include "embedded/openapi_json.h"  // generated from service/openapi.json: openapi_json()
#include "service/version.h"

namespace rollgap::service {
namespace {

using api::concat;
using nlohmann::json;

std::string unit_text(const api::Unit& unit) {
    if (unit.code == "1") return "dimensionless";
    return concat("unit ", unit.code, " (UCUM)");
}

json leaf_schema(const api::ScenarioField& field, const json& default_value, bool patch) {
    json schema = json::object();
    const auto nullable = [patch](std::string_view type) {
        return patch ? json::array({type, "null"}) : json(type);
    };
    std::string description;
    switch (field.kind) {
        case api::FieldKind::number:
        case api::FieldKind::integer: {
            const bool integer = field.kind == api::FieldKind::integer;
            schema["type"] = nullable(integer ? "integer" : "number");
            if (field.range.min_open) {
                schema["exclusiveMinimum"] = field.range.min;
            } else {
                schema["minimum"] = field.range.min;
            }
            if (field.range.max_open) {
                schema["exclusiveMaximum"] = field.range.max;
            } else {
                schema["maximum"] = field.range.max;
            }
            if (field.even) schema["multipleOf"] = 2;
            if (!integer) schema["x-unit"] = field.unit.code;
            description = concat(integer ? "Integer" : "Number", field.even ? ", even" : "", "; ",
                                 integer ? std::string("dimensionless") : unit_text(field.unit), "; bounds ",
                                 field.range.text(), ".");
            break;
        }
        case api::FieldKind::boolean:
            schema["type"] = nullable("boolean");
            description = "Boolean.";
            break;
        case api::FieldKind::choice: {
            json choices = json::array();
            for (const std::string_view choice : field.choices) choices.push_back(choice);
            if (patch) choices.push_back(nullptr);
            schema["enum"] = std::move(choices);
            description = concat("One of: ", api::choices_text(field.choices), ".");
            break;
        }
    }
    if (!default_value.is_null()) schema["default"] = default_value;
    if (patch) description += " null restores the default.";
    schema["description"] = std::move(description);
    return schema;
}

json group_schema(std::string_view path, const json& defaults, bool patch) {
    json properties = json::object();
    json required = json::array();
    for (const std::string_view member : api::scenario_group_members(path)) {
        const std::string child = concat(path, "/", member);
        const json& child_default = defaults.contains(member) ? defaults.at(std::string(member)) : json();
        if (api::is_scenario_group(child)) {
            properties[std::string(member)] = group_schema(child, child_default, patch);
        } else if (const api::ScenarioField* field = api::find_scenario_field(child)) {
            properties[std::string(member)] = leaf_schema(*field, child_default, patch);
        }
        required.push_back(member);
    }
    json schema = {
        {"type", patch ? json::array({"object", "null"}) : json("object")},
        {"additionalProperties", false},
        {"properties", std::move(properties)},
    };
    if (!patch) schema["required"] = std::move(required);
    return schema;
}

// The component a property schema refers to ({"$ref": "#/components/schemas/X"}), or nullptr.
json* referenced_schema(json& schemas, const json& property) {
    const auto ref = property.find("$ref");
    if (ref == property.end() || !ref->is_string()) return nullptr;
    constexpr std::string_view prefix = "#/components/schemas/";
    const std::string& target = ref->get_ref<const std::string&>();
    if (!std::string_view(target).starts_with(prefix)) return nullptr;
    const auto found = schemas.find(target.substr(prefix.size()));
    return found == schemas.end() ? nullptr : &*found;
}

// Sets "default" on the properties of `schema` from the options an analysis resolved from an
// empty request: the defaults live in core, the document shows them.
void add_defaults(json& schemas, json& schema, const json& resolved) {
    if (!resolved.is_object() || !schema.contains("properties")) return;
    json& properties = schema["properties"];
    for (const auto& [name, value] : resolved.items()) {
        // Defaults that depend on the request are described, not stated.
        if (name == "speeds_m_per_s" || name == "parameter" || name == "values" || name == "range") continue;
        const auto property = properties.find(name);
        if (property == properties.end()) continue;
        if (json* target = referenced_schema(schemas, *property)) {
            add_defaults(schemas, *target, value);
        } else if (!value.is_object()) {
            (*property)["default"] = value;
        }
    }
}

// Options schema of each analysis, and an options object that is valid for it.
struct OptionsSchema {
    std::string_view analysis;
    std::string_view schema;
    const char* minimal_options;
    const char* member = "";  // the defaults are this member of the resolved options ("": all)
};
constexpr std::array<OptionsSchema, 7> options_schemas{{
    {"roll_gap", "RollGapOptions", "{}"},
    {"tension_cycle", "TensionCycleOptions", "{}"},
    {"stability", "StabilityOptions", "{}"},
    {"amplitude", "AmplitudeOptions", "{}"},
    {"sweep", "SweepOptions", R"({"parameter": "/rolls/speed_m_per_s", "values": [19]})"},
    {"sweep", "SweepAmplitudeOptions",
     R"({"parameter": "/rolls/speed_m_per_s", "values": [19], "quantity": "amplitude"})", "amplitude"},
    {"evaluate", "EvaluateOptions", "{}"},
}};

void add_option_defaults(json& schemas) {
    const core::Scenario scenario{};
    for (const OptionsSchema& entry : options_schemas) {
        const Analysis* analysis = find_analysis(analyses(), entry.analysis);
        const auto schema = schemas.find(std::string(entry.schema));
        if (analysis == nullptr || schema == schemas.end()) continue;
        api::FieldErrors errors;
        // prepare() reads and resolves the options; it does not compute (analysis.h).
        const PreparedAnalysis prepared =
            analysis->prepare(scenario, json::parse(entry.minimal_options), "/options", errors);
        if (!errors.empty()) continue;
        const std::string member = entry.member;
        if (member.empty()) {
            add_defaults(schemas, *schema, prepared.resolved_options);
        } else if (prepared.resolved_options.contains(member)) {
            add_defaults(schemas, *schema, prepared.resolved_options.at(member));
        }
    }
}

}  // namespace

json scenario_json_schema(bool patch) {
    json schema = group_schema("", api::default_scenario_json(), patch);
    schema["description"] =
        patch ? "A JSON merge patch (RFC 7396) onto the default scenario (GET /v1/scenarios/default): give only "
                "the fields that differ, in the same nesting; null restores a default. Unknown fields are errors. "
                "Cross-field rules (tension below the flow stress, a small bite angle, Rayleigh frequencies in "
                "order, ...) are checked on the merged scenario."
              : "A complete scenario: every field with its unit in its name (SI prefixes, UCUM codes in x-unit). "
                "The defaults are those of GET /v1/scenarios/default.";
    return schema;
}

json openapi_document() {
    json document = json::parse(openapi_json());
    document["info"]["version"] = std::string(version());
    json& schemas = document["components"]["schemas"];
    schemas["Scenario"] = scenario_json_schema(false);
    schemas["ScenarioPatch"] = scenario_json_schema(true);

    json codes = json::array();
    for (const api::ProblemKind& kind : api::problem_kinds()) codes.push_back(kind.slug);
    schemas["Problem"]["properties"]["code"]["enum"] = std::move(codes);

    json names = json::array();
    for (const Analysis& analysis : analyses()) names.push_back(analysis.name);
    schemas["AnalysisRequest"]["properties"]["analysis"]["enum"] = std::move(names);

    json numeric_paths = json::array();
    for (const api::ScenarioField& field : api::scenario_fields()) {
        if (field.kind == api::FieldKind::number || field.kind == api::FieldKind::integer) {
            numeric_paths.push_back(field.path);
        }
    }
    schemas["SweepOptions"]["properties"]["parameter"]["enum"] = std::move(numeric_paths);
    add_option_defaults(schemas);
    return document;
}

const std::string& openapi_text() {
    static const std::string text = openapi_document().dump();
    return text;
}

}  // namespace rollgap::service
