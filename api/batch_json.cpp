#include "api/batch_json.h"

#include <algorithm>
#include <array>
#include <string>

#include "api/units.h"

namespace rollgap::api {

using nlohmann::json;

namespace {

// A member of `object` at `pointer`, or null (the answer leaves a figure out, or null).
json at(const json& object, const char* pointer) {
    const json::json_pointer where(pointer);
    return object.contains(where) ? object.at(where) : json(nullptr);
}

// speed_limit's key figures (docs/model.md §13): what a level-2 system takes from each coil.
// `mill`: tandem_speed_limit's, whose rows name stands and whose chatter limit is the mill's.
json speed_limit_headline(const json& result, bool mill) {
    json row = json::object();
    for (const char* member :
         {"status", "operating_speed_m_per_s", "advised_speed_m_per_s", "binding_limit",
          "window_min_m_per_s", "binding_min", "operating_permitted"}) {
        row[member] = result.value(member, json(nullptr));
    }
    const json& operating = row["operating_speed_m_per_s"];
    const json& advised = row["advised_speed_m_per_s"];
    const bool both = operating.is_number() && advised.is_number() && advised.get<double>() > 0.0;
    // The margin a table sorts by: how much faster the coil may run, and the share of the
    // advised speed it runs at now.
    row["speed_margin_m_per_s"] =
        both ? json(advised.get<double>() - operating.get<double>()) : json(nullptr);
    row["utilisation"] =
        both ? json(operating.get<double>() / advised.get<double>()) : json(nullptr);
    if (mill) {
        // a mill's: the stands that bind and the headline crossing (docs/model.md §13.5)
        row["binding_stand"] = result.value("binding_stand", json(nullptr));
        row["binding_min_stand"] = result.value("binding_min_stand", json(nullptr));
        row["chatter_basis"] = result.value("chatter_basis", json(nullptr));
        row["critical_speed_m_per_s"] = at(result, "/critical_speeds/critical_speed_m_per_s");
        const json headline = at(result, "/critical_speeds/headline");
        row["chatter_type"] =
            headline.is_string()
                ? at(result,
                     ("/critical_speeds/" + headline.get<std::string>() + "/chatter_type").c_str())
                : json(nullptr);
        // under the stands' posteriors (docs/model.md §13.7), the headline's
        row["critical_speed_sd_m_per_s"] = at(result, "/uncertainty/standard_deviation_m_per_s");
        row["critical_speed_lower_bound_m_per_s"] = at(result, "/uncertainty/lower_bound_m_per_s");
        row["summary"] = result.value("summary", json(nullptr));
        return row;
    }
    row["critical_speed_m_per_s"] = at(result, "/critical_speed/critical_speed_m_per_s");
    row["chatter_type"] = at(result, "/critical_speed/unstable_mode_chatter_type");
    row["critical_speed_sd_m_per_s"] = at(result, "/uncertainty/standard_deviation_m_per_s");
    row["critical_speed_lower_bound_m_per_s"] = at(result, "/uncertainty/lower_bound_m_per_s");
    row["best_change_field"] = at(result, "/what_to_change/changes/0/field");
    row["best_change_gain_m_per_s"] = at(result, "/what_to_change/changes/0/speed_gain_m_per_s");
    row["summary"] = result.value("summary", json(nullptr));
    return row;
}

// The result's scalars to two levels: a top-level member by its name, a member of a top-level
// object by both names joined with "/" as a pointer without its leading slash
// ("critical_speed/critical_speed_m_per_s", as a map's sheet names its columns). Arrays (the
// distributions, the modes) are no headline.
json scalars_of(const json& result) {
    json row = json::object();
    if (!result.is_object()) return row;
    for (const auto& [name, value] : result.items()) {
        if (!value.is_structured()) {
            row[name] = value;
        } else if (value.is_object()) {
            for (const auto& [inner, member] : value.items()) {
                if (!member.is_structured()) row[name + "/" + inner] = member;
            }
        }
    }
    return row;
}

json scalar_value_schema() {
    return {{"anyOf", json::array({{{"type", "number"}},
                                   {{"type", "string"}},
                                   {{"type", "boolean"}},
                                   {{"type", "null"}}})}};
}

json row_schema() {
    json index = integer_schema();
    index["minimum"] = 0;
    json headline = {
        {"type", "object"},
        {"description",
         "The item's key figures, flat (one CSV row). speed_limit: status, "
         "operating_speed_m_per_s, advised_speed_m_per_s, binding_limit, window_min_m_per_s, "
         "binding_min, operating_permitted, speed_margin_m_per_s (advised − operating), "
         "utilisation (operating / advised), critical_speed_m_per_s, chatter_type, "
         "critical_speed_sd_m_per_s and critical_speed_lower_bound_m_per_s (with a posterior), "
         "best_change_field and best_change_gain_m_per_s (with what_to_change), summary. "
         "tandem_speed_limit: the same to utilisation, then binding_stand, binding_min_stand, "
         "chatter_basis, critical_speed_m_per_s (the mill's headline), chatter_type, "
         "critical_speed_sd_m_per_s and critical_speed_lower_bound_m_per_s (with posteriors), "
         "summary. Any "
         "other analysis: its result's scalars to two levels, a nested one named by its path "
         "without the leading slash (critical_speed/critical_speed_m_per_s). Null when the item "
         "failed."},
        {"additionalProperties", scalar_value_schema()},
    };
    return object_schema(
        "One item of the batch: its label, how it ended, its key figures or its own problem.",
        {{"index", index},
         {"label", string_schema()},
         {"status", enum_schema({"ok", "solver_failure", "failed"})},
         {"base", ref_schema("ScenarioBase", true)},
         {"headline", {{"anyOf", json::array({headline, {{"type", "null"}}})}}},
         {"problem",
          {{"anyOf",
            json::array({{{"$ref", "#/components/schemas/Problem"}}, {{"type", "null"}}})}}},
         // only when the item has some: its values outside their typical ranges
         {"warnings", {{"$ref", "#/components/schemas/Warnings"}}}},
        {"index", "label", "status", "base", "headline", "problem"});
}

// The row's own columns, before the headline's.
constexpr std::array<const char*, 5> fixed_columns{"index", "label", "status", "base_name",
                                                   "base_version"};

// A headline member's column: its name, or result_<name> where the row has a column of that
// name (speed_limit's status beside the item's).
std::string headline_column(const std::string& name) {
    const bool taken =
        std::find(fixed_columns.begin(), fixed_columns.end(), name) != fixed_columns.end();
    return taken ? "result_" + name : name;
}

std::vector<std::string> item_columns(const json& result) {
    std::vector<std::string> columns(fixed_columns.begin(), fixed_columns.end());
    const std::size_t fixed = columns.size();
    for (const json& row : result.value("items", json::array())) {
        const json headline = row.value("headline", json());
        if (!headline.is_object()) continue;
        for (const auto& [name, value] : headline.items()) {
            const std::string column = headline_column(name);
            if (std::find(columns.begin() + static_cast<std::ptrdiff_t>(fixed), columns.end(),
                          column) == columns.end())
                columns.push_back(column);
        }
    }
    for (const char* name : {"problem_type", "problem_title", "problem_detail", "warnings"})
        columns.emplace_back(name);
    return columns;
}

// An item's warnings in one cell: each pointer with its likely plant unit ("/options/items/3/
// scenario/rolls/speed_m_per_s likely speed_m_per_min"), "; " between; null when none.
json warning_text(const json& item) {
    const json warnings = item.value("warnings", json::array());
    if (!warnings.is_array() || warnings.empty()) return nullptr;
    std::string text;
    for (const json& warning : warnings) {
        if (!text.empty()) text += "; ";
        text += warning.value("pointer", std::string());
        if (warning.contains("likely") && warning["likely"].is_object())
            text += " likely " + warning["likely"].value("key", std::string());
    }
    return text;
}

json item_rows(const json& result) {
    json rows = json::array();
    for (const json& item : result.value("items", json::array())) {
        json row = {{"index", item.value("index", json())},
                    {"label", item.value("label", json())},
                    {"status", item.value("status", json())},
                    {"base_name", at(item, "/base/name")},
                    {"base_version", at(item, "/base/version")},
                    {"problem_type", at(item, "/problem/type")},
                    {"problem_title", at(item, "/problem/title")},
                    {"problem_detail", at(item, "/problem/detail")},
                    {"warnings", warning_text(item)}};
        const json headline = item.value("headline", json());
        if (headline.is_object()) {
            for (const auto& [name, value] : headline.items()) row[headline_column(name)] = value;
        }
        rows.push_back(std::move(row));
    }
    return rows;
}

}  // namespace

json batch_headline(std::string_view analysis, const json& result) {
    if (analysis == "speed_limit") return speed_limit_headline(result, false);
    if (analysis == "tandem_speed_limit") return speed_limit_headline(result, true);
    return scalars_of(result);
}

json batch_row(std::size_t index, std::string_view label, bool failed, const json& answer) {
    json row = {{"index", index}, {"label", label}, {"base", answer.value("base", json())}};
    if (failed) {
        row["status"] = "failed";
        row["headline"] = nullptr;
        row["problem"] = answer;
        row["base"] = nullptr;
        return row;
    }
    const json result = answer.value("result", json::object());
    const std::string analysis = answer.value("analysis", std::string());
    row["headline"] = batch_headline(analysis, result);
    // A result whose solver did not converge is an answer too (a 200), but not one to trust.
    row["status"] =
        result.value("status", std::string()) == "solver_failure" ? "solver_failure" : "ok";
    row["problem"] = nullptr;
    if (answer.contains("warnings")) row["warnings"] = answer["warnings"];
    return row;
}

json batch_result_json(std::string_view analysis, json rows) {
    std::size_t failed = 0;
    for (const json& row : rows) failed += row.value("status", std::string()) == "failed" ? 1 : 0;
    return {{"analysis", analysis},
            {"items_total", rows.size()},
            {"succeeded", rows.size() - failed},
            {"failed", failed},
            {"items", std::move(rows)}};
}

std::vector<ResultSchema> batch_result_schemas() {
    json count = integer_schema();
    count["minimum"] = 0;
    json total = count;
    total["description"] = "The batch's items.";
    json succeeded = count;
    succeeded["description"] = "Items with an answer (status ok or solver_failure).";
    json failed = count;
    failed["description"] = "Items that carry their own problem instead.";
    json items = array_schema(ref_schema("BatchItem"));
    items["description"] = "One row per item, in the items' order.";
    json analysis = string_schema();
    analysis["description"] = "The analysis every item ran.";
    return {
        {"BatchItem", row_schema()},
        {"BatchResult",
         object_schema("A batch's rows: one headline per item (docs/http-api.md, \"Batches\").",
                       {{"analysis", analysis},
                        {"items_total", total},
                        {"succeeded", succeeded},
                        {"failed", failed},
                        {"items", items}},
                       {"analysis", "items_total", "succeeded", "failed", "items"})},
    };
}

std::span<const CsvTable> batch_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"items",
         "One row per item: index, label, status, base, the headline's figures, the problem.",
         "",
         {},
         "",
         item_columns,
         item_rows}};
    return tables;
}

}  // namespace rollgap::api
