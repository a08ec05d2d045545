#include "service/openapi.h"

#include <algorithm>
#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "api/calibration_json.h"
#include "api/csv.h"
#include "api/field_errors.h"
#include "api/option_table.h"
#include "api/plant_units.h"
#include "api/problem.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/tandem_json.h"
#include "api/tandem_schema.h"
#include "api/text.h"
#include "api/units.h"
#include "core/mill/mill.h"
#include "core/scenario.h"
#include "service/analyses/table.h"
#include "service/analyses/analysis.h"
#include "service/chunked.h"
#include "service/openapi_http.h"
#include "embedded/openapi_json.h"  // generated from service/openapi.json: openapi_json()
#include "service/version.h"

namespace rollgap::service {
namespace {

using api::concat;
using nlohmann::json;

std::string unit_text(const api::Unit& unit) {
    if (unit.code == "1") return "dimensionless";
    return concat("unit ", unit.code);  // the info's text says the codes are UCUM's
}

// `integer`: the bounds written as integers (2, not 2.0), as an integer option's.
void add_bounds(json& schema, const api::Interval& range, bool integer = false) {
    const auto bound = [integer](double value) {
        return integer ? json(static_cast<long long>(value)) : json(value);
    };
    schema[range.min_open ? "exclusiveMinimum" : "minimum"] = bound(range.min);
    schema[range.max_open ? "exclusiveMaximum" : "maximum"] = bound(range.max);
}

// "Number; unit m/s; bounds [0.01, 100].", "Integer, even; dimensionless; bounds [2, 64]."
std::string numeric_text(bool integer, bool even, const api::Unit& unit,
                         const api::Interval& range) {
    return concat(integer ? "Integer" : "Number", even ? ", even" : "", "; ",
                  integer ? std::string("dimensionless") : unit_text(unit), "; bounds ",
                  range.text(), ".");
}

// A choice field's enum (null too in a patch: it restores the default); its description.
std::string choice_members(json& schema, std::span<const std::string_view> choices, bool patch) {
    json values = json::array();
    for (const std::string_view choice : choices) values.push_back(choice);
    if (patch) values.push_back(nullptr);
    schema["enum"] = std::move(values);
    return concat("One of: ", api::choices_text(choices), ".");
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
            add_bounds(schema, field.range);
            if (field.even) schema["multipleOf"] = 2;
            if (!integer) schema["x-unit"] = field.unit.code;
            description = numeric_text(integer, field.even, field.unit, field.range);
            break;
        }
        case api::FieldKind::boolean:
            schema["type"] = nullable("boolean");
            description = "Boolean.";
            break;
        case api::FieldKind::choice: {
            description = choice_members(schema, field.choices, patch);
            break;
        }
    }
    if (!default_value.is_null()) schema["default"] = default_value;
    if (patch) description += " null restores the default.";
    // The glossary text of the field table first, verbatim; then type, unit and bounds.
    schema["description"] = concat(field.description, " ", description);
    schema["title"] = field.name;  // what a label or an axis calls it
    return schema;
}

// A scalar option from its row (api/option_table.h), as a scenario field's leaf: its glossary
// text, then type, unit and bounds. The reader enforces the same row.
json option_schema(const api::Option& option) {
    json schema = json::object();
    switch (option.type) {
        case api::OptionType::number:
        case api::OptionType::integer: {
            const bool integer = option.type == api::OptionType::integer;
            schema["type"] = integer ? "integer" : "number";
            add_bounds(schema, option.range, integer);
            if (!integer) schema["x-unit"] = option.unit.code;
            schema["description"] = concat(option.description, " ",
                                           numeric_text(integer, false, option.unit, option.range));
            break;
        }
        case api::OptionType::boolean:
            schema["type"] = "boolean";
            schema["description"] = option.description;
            break;
    }
    schema["title"] = option.title;  // what a label or a form calls it
    return schema;
}

// The scalar members of the options components, from the option rows; the components' compound
// members are written in openapi.json.
void add_option_members(json& schemas) {
    for (const api::OptionComponent& component : api::option_components()) {
        json& properties = schemas[std::string(component.schema)]["properties"];
        for (const api::OptionId id : component.members) {
            const api::Option& option = api::option(id);
            properties[std::string(option.name)] = option_schema(option);
        }
    }
}

// A patch's members in plant units (api/plant_units.h): beside each canonical member, the keys
// that give it in another unit, and the canonical member names them (x-alternate-units).
void add_alternates(json& properties, std::string_view member) {
    const auto alternates = api::alternates_of(member);
    if (alternates.empty()) return;
    json& canonical = properties[std::string(member)];
    json listed = json::array();
    for (const auto& [key, unit] : alternates) {
        listed.push_back({{"key", key}, {"unit", unit->unit}, {"conversion", unit->note}});
        const std::string description =
            unit->per_cross_section
                ? concat("The same quantity as ", member, " as a force in ", unit->unit, " (",
                         unit->note,
                         "), converted when the scenario is read, after every "
                         "layer is merged, and echoed as ",
                         member, "; give one of the two (null: neither from this layer).")
                : concat("The same value as ", member, " in ", unit->unit, " (", unit->note,
                         "), converted exactly and echoed as ", member, "; give one of the two.");
        json alternate;
        if (canonical.contains("properties")) {  // a group: each member in the unit
            json members = json::object();
            for (const auto& [name, leaf] : canonical["properties"].items()) {
                (void)leaf;
                members[name] = {{"type", json::array({"number", "null"})}, {"x-unit", unit->unit}};
            }
            alternate = {{"type", json::array({"object", "null"})},
                         {"additionalProperties", false},
                         {"properties", std::move(members)}};
        } else if (canonical.value("type", json()) == json("array") ||
                   (canonical.contains("type") && canonical["type"].is_array() &&
                    canonical["type"].front() == "array")) {
            // a list (the mill's spans): each value in the unit
            alternate = {{"type", json::array({"array", "null"})},
                         {"items", {{"type", "number"}, {"x-unit", unit->unit}}}};
        } else {
            alternate = {{"type", json::array({"number", "null"})}, {"x-unit", unit->unit}};
        }
        alternate["description"] = description;
        properties[key] = std::move(alternate);
    }
    properties[std::string(member)]["x-alternate-units"] = std::move(listed);
}

json group_schema(std::string_view path, const json& defaults, bool patch) {
    json properties = json::object();
    json required = json::array();
    for (const std::string_view member : api::scenario_group_members(path)) {
        const std::string child = concat(path, "/", member);
        const json& child_default =
            defaults.contains(member) ? defaults.at(std::string(member)) : json();
        if (api::is_scenario_group(child)) {
            properties[std::string(member)] = group_schema(child, child_default, patch);
        } else if (const api::ScenarioField* field = api::find_scenario_field(child)) {
            properties[std::string(member)] = leaf_schema(*field, child_default, patch);
        }
        if (patch) add_alternates(properties, member);
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

// Sets "default" on the properties of `schema` from the options an analysis resolved from a
// minimal request: the defaults live in core, the document shows them. Those that depend on the
// request (`request_dependent`) are described, not stated.
void add_defaults(json& schemas, json& schema, const json& resolved,
                  std::span<const std::string_view> request_dependent) {
    if (!resolved.is_object() || !schema.contains("properties")) return;
    json& properties = schema["properties"];
    for (const auto& [name, value] : resolved.items()) {
        if (std::find(request_dependent.begin(), request_dependent.end(), name) !=
            request_dependent.end()) {
            continue;
        }
        const auto property = properties.find(name);
        if (property == properties.end()) continue;
        if (json* target = referenced_schema(schemas, *property)) {
            add_defaults(schemas, *target, value, request_dependent);
        } else if (!value.is_object()) {
            (*property)["default"] = value;
        }
    }
}

void add_option_defaults(json& schemas) {
    const core::Scenario scenario{};
    for (const Analysis& analysis : analyses()) {
        for (const OptionsDefaults& entry : analysis.options_defaults) {
            const auto schema = schemas.find(std::string(entry.schema));
            if (schema == schemas.end()) continue;
            api::FieldErrors errors;
            // prepare() reads and resolves the options; it does not compute (analysis.h).
            const PreparedAnalysis prepared =
                analysis.subject() == Subject::mill
                    ? analysis.prepare_mill(core::default_mill(),
                                            json::parse(entry.minimal_options), "/options", errors)
                    : analysis.prepare(scenario, json::parse(entry.minimal_options), "/options",
                                       errors);
            if (!errors.empty()) continue;
            const std::string member(entry.member);
            if (member.empty()) {
                add_defaults(schemas, *schema, prepared.resolved_options,
                             analysis.request_dependent_options);
            } else if (prepared.resolved_options.contains(member)) {
                add_defaults(schemas, *schema, prepared.resolved_options.at(member),
                             analysis.request_dependent_options);
            }
        }
    }
}

json component_ref(std::string_view component) {
    return {{"$ref", concat("#/components/schemas/", component)}};
}

// "base" in every request that carries a scenario or a tandem patch (the analysis routes' bodies
// and the full request of a job), typed once here rather than in each request schema.
void add_base(json& schemas) {
    const auto base = [](std::string_view description) {
        return json{{"allOf", json::array({component_ref("ScenarioName")})},
                    {"description", description}};
    };
    const json stand = base(
        "The name of a stored scenario (PUT /v1/scenarios/{name}): `scenario` is merged onto it "
        "instead of the default (null in the patch still restores the built-in default). The "
        "result echoes it as `base` {name, version}. 422 at /base when no such scenario is "
        "stored; 503 store_unavailable when the store cannot be reached. Absent: the store is "
        "not used.");
    const json mill = base(
        "The name of a stored mill (PUT /v1/mills/{name}): `tandem` is merged onto it instead of "
        "the default mill (arrays such as `stands` are replaced whole). The result echoes it as "
        "`base` {name, version}. 422 at /base when no such mill is stored or the name holds a "
        "stand scenario; 503 store_unavailable when the store cannot be reached. Absent: the "
        "store is not used.");
    const json either = base(
        "The name of a stored scenario (a stand's analysis: `scenario` is merged onto it) or of "
        "a stored mill (a mill's analysis, `tandem`: PUT /v1/mills/{name}); the kind must match "
        "the analysis. The result echoes it as `base` {name, version}. 422 at /base when no "
        "such document is stored; 503 store_unavailable when the store cannot be reached.");
    for (auto& [name, schema] : schemas.items()) {
        if (!std::string_view(name).ends_with("Request") || !schema.contains("properties"))
            continue;
        const bool of_stand = schema["properties"].contains("scenario");
        const bool of_mill = schema["properties"].contains("tandem");
        if (of_stand || of_mill)
            schema["properties"]["base"] = of_stand && of_mill ? either : of_stand ? stand : mill;
    }
}

// Accept: text/csv on a response that holds a result of these analyses: the tables, the
// ?table= parameter and the 406 when there is none.
void add_csv(json& operation, json& ok, std::span<const Analysis> analyses_here) {
    json names = json::array();
    std::string list;
    for (const Analysis& analysis : analyses_here) {
        for (const api::CsvTable& table : analysis.tables()) {
            if (std::find(names.begin(), names.end(), table.name) == names.end())
                names.push_back(table.name);
            list += concat(list.empty() ? "" : "; ", analysis.name, " `", table.name,
                           "`: ", table.description);
        }
    }
    operation["responses"]["406"] = {{"$ref", "#/components/responses/NotAcceptable"}};
    if (names.empty()) return;
    ok["content"][std::string(api::csv_media_type)] = {
        {"schema", {{"type", "string"}}},
        {"example",
         "speed_m_per_s,stable,max_growth_rate_per_s,steady_status\r\n10,true,-19.09,ok\r\n"}};
    ok["description"] = concat(
        ok.value("description", std::string()),
        " With `Accept: text/csv`: one table of the result as RFC 4180 CSV (header row of column names with their "
        "units, CRLF line ends, empty field for null); `table` picks it, the first listed is the default. Tables: ",
        list, ".");
    operation["parameters"].push_back({
        {"name", "table"},
        {"in", "query"},
        {"required", false},
        {"description",
         "With Accept: text/csv, the table of the result to return (default: the analysis' first)."},
        {"schema", {{"enum", std::move(names)}}},
    });
    operation["parameters"].push_back({
        {"name", "units"},
        {"in", "query"},
        {"required", false},
        {"description",
         "With Accept: text/csv, the units of the table's columns: si (the JSON's, the default) "
         "or plant (a column in m/s renamed _m_per_min and converted to m/min, one in Pa.s "
         "renamed _mPa_s and converted to mPa.s; the other columns as they are). The JSON answer "
         "is always canonical. Another value: 422 at /query/units."},
        {"schema", {{"type", "string"}, {"enum", {"si", "plant"}}, {"default", "si"}}},
    });
}

void add_result_schemas(json& document) {
    json& schemas = document["components"]["schemas"];
    json responses = json::array();
    json mapping = json::object();
    for (const Analysis& analysis : analyses()) {
        for (api::ResultSchema& component : analysis.result_schemas()) {
            schemas[std::string(component.component)] = std::move(component.schema);
        }
        const std::string response(analysis.response_schema);
        if (analysis.subject() == Subject::batch) {
            // No subject of its own; its route answers a job (openapi.json), whose result this is.
            schemas[response] = {
                {"type", "object"},
                {"description",
                 concat("The ", analysis.name,
                        " analysis' answer (a job's result): the options it used, without the "
                        "items (the rows list them by index and label), and the rows.")},
                {"required", {"analysis", "options", "result"}},
                {"additionalProperties", false},
                {"properties",
                 {{"analysis",
                   {{"const", analysis.name}, {"description", "The analysis that ran."}}},
                  {"options",
                   {{"type", "object"},
                    {"description",
                     "The batch's options without its items, and "
                     "items_total."}}},
                  {"result", component_ref(analysis.result_schema)}}},
            };
            responses.push_back(component_ref(response));
            mapping[std::string(analysis.name)] = concat("#/components/schemas/", response);
            continue;
        }
        const bool of_mill = analysis.subject() == Subject::mill;
        const char* subject = of_mill ? "tandem" : "scenario";
        schemas[response] = {
            {"type", "object"},
            {"description", concat("The ", analysis.name, " analysis' answer: the complete ",
                                   of_mill ? "mill" : "scenario",
                                   " and the options it used (so it can be rerun) and the "
                                   "result.")},
            {"required", {"analysis", subject, "options", "result"}},
            {"additionalProperties", false},
            {"properties",
             {{"analysis", {{"const", analysis.name}, {"description", "The analysis that ran."}}},
              {subject, component_ref(of_mill ? "Tandem" : "Scenario")},
              {"options", component_ref(analysis.options_schema)},
              {"result", component_ref(analysis.result_schema)}}},
        };
        schemas[response]["properties"]["base"] = component_ref("ScenarioBase");
        schemas[response]["properties"]["warnings"] = component_ref("Warnings");
        responses.push_back(component_ref(response));
        mapping[std::string(analysis.name)] = concat("#/components/schemas/", response);

        json& operation = document["paths"][std::string(analysis.path)]["post"];
        json& ok = operation["responses"]["200"];
        ok["content"]["application/json"]["schema"] = component_ref(response);
        add_csv(operation, ok, std::span(&analysis, 1));
    }
    schemas["AnalysisResponse"] = {
        {"description",
         "An analysis' answer (a job's result): the analysis, the complete scenario and the options "
         "it used, and the result typed per analysis."},
        {"oneOf", std::move(responses)},
        {"discriminator", {{"propertyName", "analysis"}, {"mapping", std::move(mapping)}}},
    };
    json& get_job = document["paths"]["/v1/jobs/{id}"]["get"];
    add_csv(get_job, get_job["responses"]["200"], analyses());
}

// A job's request: each analysis' options component, required where the analysis needs
// options (its component requires members: a sweep's parameter, a fit's observations), from
// the rows, so an analysis added later is typed too.
void add_analysis_request_options(json& schemas) {
    json cases = json::array();
    for (const Analysis& analysis : analyses()) {
        if (analysis.options_schema.empty()) continue;
        const std::string component(analysis.options_schema);
        json then = {{"properties", {{"options", component_ref(component)}}}};
        const json& options = schemas[component];
        if (options.contains("required") && !options["required"].empty())
            then["required"] = json::array({"options"});
        cases.push_back({{"if",
                          {{"properties", {{"analysis", {{"const", analysis.name}}}}},
                           {"required", json::array({"analysis"})}}},
                         {"then", std::move(then)}});
    }
    schemas["AnalysisRequest"]["allOf"] = std::move(cases);
}

// The analyses as the descriptor's rows, in order (x-rollgap-analyses): what a client such as
// the workbench page lists without a copy of its own. `csv`: the result has CSV tables (its route
// answers Accept: text/csv); `on_page`: the workbench offers it.
json analysis_list() {
    json list = json::array();
    for (const Analysis& analysis : analyses()) {
        list.push_back({
            {"name", analysis.name},
            {"label", analysis.label},
            {"summary", analysis.summary},
            {"path", analysis.path},
            {"options_schema", analysis.options_schema},
            {"csv", !analysis.tables().empty()},
            {"pointwise", analysis.pointwise()},
            {"on_page", analysis.on_page},
            {"subject", analysis.subject() == Subject::mill    ? "tandem"
                        : analysis.subject() == Subject::batch ? "items"
                                                               : "scenario"},
        });
    }
    return list;
}

}  // namespace

json scenario_json_schema(bool patch) {
    json schema = group_schema("", api::default_scenario_json(), patch);
    schema["description"] =
        patch
            ? "A JSON merge patch (RFC 7396) onto the default scenario (GET /v1/scenarios/default): give only "
              "the fields that differ, in the same nesting; null restores a default. Unknown fields are errors. "
              "Cross-field rules (tension below the flow stress, a small bite angle, Rayleigh frequencies in "
              "order, ...) are checked on the merged scenario."
            : "A complete scenario: every field with its unit in its name (SI prefixes, UCUM codes in x-unit). "
              "The defaults are those of GET /v1/scenarios/default.";
    return schema;
}

namespace {

// A field of the tandem document (api/tandem_schema.h), as a scenario field's leaf.
json tandem_leaf_schema(const api::TandemField& field, const json& default_value, bool patch) {
    const auto nullable = [patch](std::string_view type) {
        return patch ? json::array({type, "null"}) : json(type);
    };
    json schema = json::object();
    std::string description;
    switch (field.kind) {
        case api::TandemFieldKind::number:
            schema["type"] = nullable(field.integer ? "integer" : "number");  // a count is whole
            add_bounds(schema, field.range);
            schema["x-unit"] = field.unit.code;
            description = numeric_text(field.integer, false, field.unit, field.range);
            break;
        case api::TandemFieldKind::number_list: {
            json item = {{"type", "number"}, {"x-unit", field.unit.code}};
            add_bounds(item, field.range);
            schema["type"] = nullable("array");
            schema["items"] = std::move(item);
            schema["maxItems"] = core::max_mill_stands;
            description =
                concat("Array of numbers, ",
                       field.length == api::ListLength::stands ? "one per stand"
                                                               : "one per interstand span",
                       "; each: ", numeric_text(false, false, field.unit, field.range));
            break;
        }
        case api::TandemFieldKind::choice: {
            description = choice_members(schema, field.choices, patch);
            break;
        }
    }
    if (!default_value.is_null()) schema["default"] = default_value;
    if (patch) description += " null restores the default.";
    schema["description"] = concat(field.description, " ", description);
    schema["title"] = field.name;
    return schema;
}

// A stand of the tandem document: a scenario merge patch, which may name a stored stand
// (docs/http-api.md, "Stored stands in a mill").
json mill_stand_schema() {
    json schema = scenario_json_schema(true);
    schema["properties"]["base"] = {
        {"anyOf", json::array({component_ref("ScenarioName"), component_ref("ScenarioBase"),
                               json{{"type", "null"}}})},
        {"description",
         "A stored stand scenario's name (PUT /v1/scenarios/{name}; the service only): the stand "
         "is that scenario without the fields the mill gives every stand, with the rest of this "
         "patch merged over it (stand_defaults do not reach it). Echoed resolved, {name, "
         "version}: that form is the service's to write (a job's stored request), over HTTP "
         "a stand's base is a name. A mill speed limit without "
         "options.posteriors takes the stand's stored calibration posterior while it still "
         "describes the stand. 422 at this pointer when no such stand is stored."}};
    schema["description"] =
        "One stand of a tandem mill: a scenario merge patch, or a stored stand (`base`) with a "
        "patch over it.";
    return schema;
}

json tandem_group_schema(std::string_view path, const json& defaults, bool patch) {
    json properties = json::object();
    json required = json::array();
    for (const std::string_view member : api::tandem_group_members(path)) {
        const std::string child = concat(path, "/", member);
        const json& child_default =
            defaults.contains(member) ? defaults.at(std::string(member)) : json();
        if (path.empty() && member == api::stand_defaults_member) {
            properties[std::string(member)] = {
                {"allOf", json::array({component_ref("ScenarioPatch")})},
                {"description",
                 "A scenario merge patch shared by every stand (rolls, lubricant, roughness, "
                 "friction, film model, flow stress, structure), applied before each stand's own. "
                 "The fields the mill gives (a stand's thicknesses, width, Young's modulus, roll "
                 "speed and tensions) are refused here: they are the tandem document's."}};
        } else if (path.empty() && member == api::stands_member) {
            properties[std::string(member)] = {
                {"type", patch ? json::array({"array", "null"}) : json("array")},
                {"minItems", 1},
                {"maxItems", core::max_mill_stands},
                {"items", component_ref("MillStand")},
                {"description",
                 "One scenario merge patch per stand, from the entry (1 to 6 stands): the "
                 "default scenario, then stand_defaults, then this patch make the stand; or a "
                 "stored stand (`base`) with this patch over it. An array is replaced whole by a "
                 "merge patch: send every stand (`{}` for a stand that takes the shared "
                 "defaults). The stand's structure group keeps its v1 name `mill` (one stand's "
                 "masses, stiffnesses, damping)."}};
        } else if (api::is_tandem_group(child)) {
            properties[std::string(member)] = tandem_group_schema(child, child_default, patch);
        } else if (const api::TandemField* field = api::find_tandem_field(child)) {
            properties[std::string(member)] = tandem_leaf_schema(*field, child_default, patch);
        }
        if (patch) add_alternates(properties, member);
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

}  // namespace

json tandem_json_schema(bool patch) {
    json schema = tandem_group_schema("", api::default_tandem_json(), patch);
    schema["description"] =
        patch ? "A JSON merge patch (RFC 7396) onto the default mill (docs/model.md §12.3: five "
                "stands, 2.80 -> 1.20 mm at 15 m/s): give only what differs; arrays (the "
                "schedule, the spans, the stands) are replaced whole. Violations are reported "
                "with their pointers, e.g. /tandem/stands/3/rolls/radius_mm; a thickness that "
                "grows downstream or more than 6 stands is a 422."
              : "A complete tandem mill: the mill's fields with their units in their names, and "
                "each stand's complete scenario without the fields the mill gives it.";
    return schema;
}

json openapi_document() {
    json document = json::parse(openapi_json());
    document["info"]["version"] = std::string(version());
    json& schemas = document["components"]["schemas"];
    schemas["Scenario"] = scenario_json_schema(false);
    schemas["ScenarioPatch"] = scenario_json_schema(true);
    schemas["MillStand"] = mill_stand_schema();
    schemas["Tandem"] = tandem_json_schema(false);
    schemas["TandemPatch"] = tandem_json_schema(true);
    // A running chunked job's points so far, typed by the result tables' point components.
    json& partial = schemas["Job"]["properties"]["partial_result"];
    json typed = partial_result_schema(analyses());
    typed["description"] = partial.value("description", "");
    partial = std::move(typed);

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
    schemas["SweepOptions"]["properties"]["parameter"]["enum"] = numeric_paths;
    // A map's axes: any numeric field but the roll speed (the search scans it); a fit's
    // parameters: the continuous ones.
    json map_paths = json::array();
    json fitted_paths = json::array();
    for (const api::ScenarioField& field : api::scenario_fields()) {
        if (field.kind == api::FieldKind::number) fitted_paths.push_back(field.path);
        if ((field.kind == api::FieldKind::number || field.kind == api::FieldKind::integer) &&
            field.path != "/rolls/speed_m_per_s")
            map_paths.push_back(field.path);
    }
    schemas["MapAxis"]["properties"]["parameter"]["enum"] = std::move(map_paths);
    schemas["CalibrateOptions"]["properties"]["parameters"]["items"]["properties"]["field"]
           ["enum"] = std::move(fitted_paths);
    // A fit's observed quantities from their table, each with its title and UCUM unit, in the
    // enum's order (x-enum-descriptions as generators read it; x-units for a label's unit).
    json quantities = json::array();
    json quantity_titles = json::array();
    json quantity_units = json::array();
    for (const api::CalibrationQuantity& q : api::calibration_quantities()) {
        quantities.push_back(q.name);
        quantity_titles.push_back(q.title);
        quantity_units.push_back(q.unit.code);
    }
    json& quantity = schemas["CalibrateOptions"]["properties"]["observations"]["items"]
                            ["properties"]["quantity"];
    quantity["enum"] = std::move(quantities);
    quantity["x-enum-descriptions"] = std::move(quantity_titles);
    quantity["x-units"] = std::move(quantity_units);
    add_analysis_request_options(schemas);
    add_base(schemas);
    add_option_members(schemas);
    add_option_defaults(schemas);
    add_result_schemas(document);
    document["x-rollgap-analyses"] = analysis_list();
    split_request_components(document);
    add_http_conventions(document);
    return document;
}

const std::string& openapi_text() {
    static const std::string text = openapi_document().dump();
    return text;
}

}  // namespace rollgap::service
