#include "service/scenario_explain.h"

#include <algorithm>
#include <cctype>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/plant_units.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/tandem_json.h"
#include "api/tandem_schema.h"
#include "api/text.h"

namespace rollgap::service {
namespace {

using api::concat;

constexpr std::size_t text_width = 96;
constexpr std::string_view indent = "    ";

std::string unit_column(const api::ScenarioField& field) {
    switch (field.kind) {
        case api::FieldKind::number: return std::string(field.unit.code);
        case api::FieldKind::integer: return "1";
        case api::FieldKind::boolean:
        case api::FieldKind::choice: break;
    }
    return "-";
}

std::string bounds_column(const api::ScenarioField& field) {
    switch (field.kind) {
        case api::FieldKind::number: return field.range.text();
        case api::FieldKind::integer: return concat(field.range.text(), field.even ? ", even" : "");
        case api::FieldKind::boolean: return "true | false";
        case api::FieldKind::choice: return api::choices_text(field.choices);
    }
    return "";
}

// Words of `text` on lines of at most text_width bytes (a longer word keeps its own line). A
// short word after a number ("20–80 t", "5–30 m/s") stays with it: a unit never starts a line.
void append_wrapped(std::string& out, std::string_view text) {
    std::vector<std::string> words;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find(' ', start);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view word = text.substr(start, end - start);
        start = end + 1;
        if (word.empty()) continue;
        const bool after_number =
            !words.empty() && std::isdigit(static_cast<unsigned char>(words.back().back()));
        if (after_number && word.size() <= 4) {
            words.back() += concat(" ", word);
        } else {
            words.emplace_back(word);
        }
    }
    std::size_t line_length = 0;
    for (const std::string& word : words) {
        if (line_length > 0 && line_length + 1 + word.size() > text_width) {
            out += '\n';
            line_length = 0;
        }
        if (line_length == 0) {
            out += indent;
            line_length = indent.size();
        } else {
            out += ' ';
            ++line_length;
        }
        out += word;
        line_length += word.size();
    }
    out += '\n';
}

std::string padded(std::string text, std::size_t width) {
    if (text.size() < width) text.append(width - text.size(), ' ');
    return text;
}

}  // namespace

namespace {

// One entry of the glossary: its line (pointer, unit, bounds, default) and its text below.
struct GlossaryRow {
    std::string pointer, unit, bounds, default_value, description;
};

std::string default_text(const nlohmann::json& value) {
    return value.is_string() ? value.get<std::string>() : value.dump();
}

// The header line, then each row's line and its wrapped description, columns as wide as their
// widest entry.
std::string glossary_table(const std::vector<GlossaryRow>& rows) {
    const GlossaryRow header{"pointer", "unit", "bounds", "default", ""};
    std::size_t pointer_width = header.pointer.size(), unit_width = header.unit.size();
    std::size_t bounds_width = header.bounds.size();
    for (const GlossaryRow& row : rows) {
        pointer_width = std::max(pointer_width, row.pointer.size());
        unit_width = std::max(unit_width, row.unit.size());
        bounds_width = std::max(bounds_width, row.bounds.size());
    }
    const auto line = [&](const GlossaryRow& row) {
        return concat(padded(row.pointer, pointer_width + 2), padded(row.unit, unit_width + 2),
                      padded(row.bounds, bounds_width + 2), row.default_value, "\n");
    };
    std::string out = line(header);
    for (const GlossaryRow& row : rows) {
        out += '\n';
        out += line(row);
        append_wrapped(out, row.description);
    }
    return out;
}

// The plant-unit keys (api/plant_units.h) of every field and group of a table, one line each.
void add_plant_units(std::string& out, std::string_view where,
                     const std::vector<std::string>& paths) {
    std::vector<std::string> seen;
    for (const std::string& path : paths) {
        // the field itself and each group above it (masses_t: masses_kg)
        for (std::size_t end = path.size(); end != std::string::npos && end > 0;
             end = path.rfind('/', end - 1)) {
            const std::string target = path.substr(0, end);
            if (std::find(seen.begin(), seen.end(), target) != seen.end()) continue;
            seen.push_back(target);
            const std::size_t slash = target.rfind('/');
            for (const auto& [key, unit] : api::alternates_of(target.substr(slash + 1))) {
                out += concat(padded(concat(where, target), 38),
                              padded(concat(where, target.substr(0, slash + 1), key), 40),
                              padded(std::string(unit->unit), 8), unit->note, "\n");
            }
            if (end == 0) break;
        }
    }
}

}  // namespace

std::string scenario_explanation() {
    const nlohmann::json defaults = api::default_scenario_json();
    std::vector<GlossaryRow> rows;
    for (const api::ScenarioField& field : api::scenario_fields()) {
        rows.push_back({field.path, unit_column(field), bounds_column(field),
                        default_text(defaults.at(nlohmann::json::json_pointer(field.path))),
                        field.description});
    }
    std::string out =
        "The scenario's fields. A request's \"scenario\" is a JSON merge patch onto the defaults: give only the\n"
        "fields you change, at these JSON pointers (relative to \"scenario\"), in the unit their name carries\n"
        "(or in a plant unit, where a field lists one: \"speed_m_per_min\": 900 is 15 m/s).\n"
        "The model and its symbols: docs/model.md.\n\n";
    out += glossary_table(rows);
    out += tandem_explanation();
    out += plant_unit_explanation();
    return out;
}

std::string plant_unit_explanation() {
    std::string out =
        "\n\nPlant units. A field (or a group) may be given under the key of a plant unit instead "
        "of its own: the\nvalue is converted exactly and echoed in the field's unit; one member "
        "in two forms is refused.\n\n";
    out += concat(padded("field", 38), padded("plant-unit key", 40), padded("unit", 8),
                  "conversion\n");
    std::vector<std::string> stand, mill;
    for (const api::ScenarioField& field : api::scenario_fields()) stand.push_back(field.path);
    for (const api::TandemField& field : api::tandem_fields()) mill.push_back(field.path);
    add_plant_units(out, "/scenario", stand);
    add_plant_units(out, "/tandem", mill);
    return out;
}

std::string tandem_explanation() {
    const nlohmann::json defaults = api::default_tandem_json();
    std::vector<GlossaryRow> rows;
    for (const api::TandemField& field : api::tandem_fields()) {
        const bool choice = field.kind == api::TandemFieldKind::choice;
        std::string bounds = choice ? api::choices_text(field.choices) : field.range.text();
        if (field.kind == api::TandemFieldKind::number_list) {
            bounds = concat(bounds,
                            field.length == api::ListLength::stands ? " per stand" : " per span");
        }
        rows.push_back({field.path, choice ? "-" : std::string(field.unit.code), std::move(bounds),
                        default_text(defaults.at(nlohmann::json::json_pointer(field.path))),
                        field.description});
    }
    rows.push_back({concat("/", api::stand_defaults_member), "-", "scenario patch", "{}",
                    "A scenario merge patch shared by every stand (the fields above the tandem "
                    "section, except a stand's thicknesses, width, Young's modulus, roll speed and "
                    "tensions, which the mill gives)."});
    rows.push_back({concat("/", api::stands_member), "-", "1 to 6 scenario patches",
                    "[{}, {}, {}, {}, {}]",
                    "One scenario merge patch per stand, from the entry: the default scenario, "
                    "then stand_defaults, then this patch. A violation in stand 4 is reported at "
                    "/tandem/stands/3/...; its structure group keeps the scenario's name `mill`."});
    return "\n\nThe tandem mill's fields (analysis \"tandem\", docs/model.md §12). A request's "
           "\"tandem\" is a JSON merge\npatch onto the default 5-stand mill, at these pointers "
           "(relative to \"tandem\"); arrays are replaced whole.\n\n" +
           glossary_table(rows);
}

}  // namespace rollgap::service
