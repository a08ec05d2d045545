// The mill's change fields (tandem-document pointers with their steps) and the answer's
// what_to_change (api/tandem_change_json.h; docs/model.md §13.6).
#include "api/tandem_change_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "api/options_reader.h"
#include "api/scenario_schema.h"
#include "api/speed_limit_json.h"
#include "api/tandem_result_json.h"
#include "api/tandem_schema.h"
#include "api/text.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside the other tandem files.
namespace tandem_change_detail {

using nlohmann::json;
using std::string_view_literals::operator""sv;

constexpr std::string_view stands_prefix = "/stands/";
constexpr std::string_view defaults_prefix = "/stand_defaults/";
constexpr std::array<std::string_view, 2> change_members{"field"sv, "step"sv};
constexpr std::string_view forms =
    "/stands/{i}/<scenario number field>, /stand_defaults/<scenario number field>, a mill number "
    "(/entry/tension_MPa) or /<mill list>/{k} (/spans/tension_MPa/0)";

// A list index: digits without a leading zero, below `count`.
std::optional<int> read_index(std::string_view text, int count) {
    if (text.empty() || text.size() > 2 || (text.size() > 1 && text[0] == '0')) return std::nullopt;
    int value = 0;
    for (const char c : text) {
        if (c < '0' || c > '9') return std::nullopt;
        value = 10 * value + (c - '0');
    }
    if (value >= count) return std::nullopt;
    return value;
}

// A stand's scenario number a change may move: continuous, not given to the stand by the mill.
const ScenarioField* stand_scenario_number(std::string_view path, int stand, int stands,
                                           std::string& why) {
    const ScenarioField* field = find_scenario_field(path);
    if (field == nullptr || field->kind != FieldKind::number) {
        why = concat(quoted_for_message(path),
                     " is not a continuous number field of a stand's scenario");
        return nullptr;
    }
    why = mill_given_field_message(path, stand, stands);
    if (!why.empty()) return nullptr;
    return field;
}

MillChangeField stand_field(std::string path, const ScenarioField* field, int stand) {
    const auto read = [field](const core::Scenario& s) {
        core::Scenario copy = s;
        return field->number(copy);
    };
    MillChangeField out;
    out.path = std::move(path);
    out.unit = field->unit;
    out.range = field->range;
    if (stand >= 0) {
        const auto at = static_cast<std::size_t>(stand);
        out.value = [read, at](const core::Mill& m) -> std::optional<double> {
            if (at >= m.stands.size()) return std::nullopt;
            return read(m.stands[at]);
        };
        out.values = [read, at](const core::Mill& m) {
            return at < m.stands.size() ? std::vector<double>{read(m.stands[at])}
                                        : std::vector<double>{};
        };
        out.shift = [field, at](core::Mill& m, double delta) {
            if (at < m.stands.size()) field->number(m.stands[at]) += delta;
        };
        return out;
    }
    out.values = [read](const core::Mill& m) {
        std::vector<double> values;
        for (const core::Scenario& s : m.stands) values.push_back(read(s));
        return values;
    };
    out.value = [values = out.values](const core::Mill& m) -> std::optional<double> {
        const std::vector<double> all = values(m);
        if (all.empty() ||
            std::any_of(all.begin(), all.end(), [&all](double v) { return v != all.front(); }))
            return std::nullopt;
        return all.front();
    };
    out.shift = [field](core::Mill& m, double delta) {
        for (core::Scenario& s : m.stands) field->number(s) += delta;
    };
    return out;
}

// A number of the mill's own table, or an element of one of its lists.
std::optional<MillChangeField> mill_field(std::string_view path, int stands, std::string& why) {
    if (path == "/speed_m_per_s") {
        why = "the mill speed is what the speed limit answers, not a change to it";
        return std::nullopt;
    }
    if (const TandemField* field = find_tandem_field(path)) {
        if (field->kind != TandemFieldKind::number || field->integer) {
            why = concat(quoted_for_message(path),
                         field->kind == TandemFieldKind::number_list
                             ? " is a list: name one element, " + std::string(path) + "/0"
                             : " is not a continuous number");
            return std::nullopt;
        }
        MillChangeField out;
        out.path = std::string(path);
        out.unit = field->unit;
        out.range = field->range;
        out.value = [get = field->get](const core::Mill& m) { return std::optional(get(m)); };
        out.values = [get = field->get](const core::Mill& m) { return std::vector{get(m)}; };
        out.shift = [get = field->get, set = field->set](core::Mill& m, double delta) {
            set(m, get(m) + delta);
        };
        return out;
    }
    const std::size_t slash = path.rfind('/');
    const TandemField* list =
        slash == std::string_view::npos ? nullptr : find_tandem_field(path.substr(0, slash));
    if (list == nullptr || list->kind != TandemFieldKind::number_list) {
        why = concat(quoted_for_message(path), " is not a number of the tandem document");
        return std::nullopt;
    }
    const int most = stands > 0 ? stands : core::max_mill_stands;
    const int count = list->length == ListLength::stands ? most : most - 1;
    const std::optional<int> index = read_index(path.substr(slash + 1), count);
    if (!index) {
        why = concat(quoted_for_message(path), " names no element of ", list->path, " (0 to ",
                     std::to_string(count - 1), ")");
        return std::nullopt;
    }
    const auto at = static_cast<std::size_t>(*index);
    MillChangeField out;
    out.path = std::string(path);
    out.unit = list->unit;
    out.range = list->range;
    out.value = [get = list->get_list, at](const core::Mill& m) -> std::optional<double> {
        const std::vector<double> values = get(m);
        if (at >= values.size()) return std::nullopt;
        return values[at];
    };
    out.values = [value = out.value](const core::Mill& m) {
        const std::optional<double> v = value(m);
        return v ? std::vector{*v} : std::vector<double>{};
    };
    out.shift = [get = list->get_list, set = list->set_list, at](core::Mill& m, double delta) {
        std::vector<double> values = get(m);
        if (at >= values.size()) return;
        values[at] += delta;
        set(m, values);
    };
    return out;
}

// --- the answer ----------------------------------------------------------------------------

struct Row {
    const MillChangeField* field = nullptr;
    std::optional<double> value;       // SI
    std::optional<double> derivative;  // m/s per SI unit
    bool within_bounds = true;

    std::optional<double> gain() const {
        if (!derivative) return std::nullopt;
        return std::abs(*derivative * field->step);
    }
};

// The rows ranked by the speed a typical step gains (rows without a derivative last, in the
// request's order).
std::vector<Row> rows_of(const MillWhatToChange& w) {
    std::vector<Row> rows;
    for (std::size_t j = 0; j < w.changes.size(); ++j) {
        const MillChangeField& c = w.changes[j];
        Row row{&c, c.value(w.mill), w.sensitivity.binding.derivatives[j]};
        if (row.derivative) {
            const double step = *row.derivative >= 0.0 ? c.step : -c.step;
            for (const double v : c.values(w.mill))
                if (!c.range.contains(from_si(v + step, c.unit))) row.within_bounds = false;
        }
        rows.push_back(row);
    }
    std::stable_sort(rows.begin(), rows.end(), [](const Row& a, const Row& b) {
        return a.gain().value_or(-1.0) > b.gain().value_or(-1.0);
    });
    return rows;
}

const ResultTable<Row>& row_table() {
    static const ResultTable<Row> table{
        "TandemSpeedLimitChange",
        "One number of the mill a plant can set: how the advised mill speed moves with it, per "
        "unit and per typical step, at the binding limit.",
        {
            {"field", "Its JSON pointer in the tandem document (options.changes).", string_schema(),
             [](const Row& r) { return json(r.field->path); }},
            {"unit", "Its unit (UCUM code): of value and step.", string_schema(),
             [](const Row& r) { return json(r.field->unit.code); }},
            {"value", "The mill's value; null for a /stand_defaults/ field whose stands differ.",
             number_schema(units::one),
             [](const Row& r) {
                 return r.value ? json(from_si(*r.value, r.field->unit)) : json(nullptr);
             }},
            {"step", "The typical step (options.changes).", number_schema(units::one, false),
             [](const Row& r) { return json(from_si(r.field->step, r.field->unit)); }},
            {"advised_speed_change_m_per_s_per_unit",
             "d(advised mill speed)/d(field) in m/s per the field's unit; null where the model "
             "had no answer at a difference point.",
             number_schema(units::one),
             [](const Row& r) {
                 if (!r.derivative) return json(nullptr);
                 return json(*r.derivative * to_si(1.0, r.field->unit));
             }},
            {"speed_gain_m_per_s",
             "What one typical step in `direction` gains, to first order (the same limit still "
             "binding).",
             number_schema(units::metre_per_second),
             [](const Row& r) { return r.gain() ? json(*r.gain()) : json(nullptr); }},
            {"direction", "raise or lower the field to gain speed; null without a derivative.",
             enum_schema({"raise", "lower"}, true),
             [](const Row& r) {
                 if (!r.derivative) return json(nullptr);
                 return json(*r.derivative >= 0.0 ? "raise" : "lower");
             }},
            {"within_bounds",
             "Whether the step in that direction keeps every value it moves inside the field's "
             "bounds.",
             boolean_schema(), [](const Row& r) { return json(r.within_bounds); }},
        }};
    return table;
}

std::string stand_text(int index) { return concat("stand ", std::to_string(index + 1)); }

std::string note(const MillWhatToChange& w) {
    const core::BindingSensitivity& b = w.sensitivity.binding;
    if (!b.kind)
        return "No limit binds below the range's highest speed: nothing to gain by a change.";
    if (*b.kind == core::SpeedLimitKind::steady_state)
        return "The mill loses its steady state above the advised speed: that edge has no margin "
               "to differentiate.";
    if (!b.ok) return "The binding limit's margin could not be differentiated there.";
    constexpr std::string_view first_order =
        " First order: a step large enough for another limit to bind gains less.";
    if (*b.kind == core::SpeedLimitKind::chatter) {
        const std::string moving = w.sensitivity.stand >= 0
                                       ? concat(", ", stand_text(w.sensitivity.stand), " moving")
                                       : std::string();
        return concat("The chatter limit binds: a change moves the ",
                      core::to_string(*w.sensitivity.crossing), " crossing (",
                      summary_speed_text(b.speed), moving, "), and the advised mill speed by ",
                      format_number(1.0 - w.chatter_margin), " of that (the margin held).",
                      first_order);
    }
    return concat("The ", core::to_string(*b.kind), " limit of ", stand_text(w.sensitivity.stand),
                  " binds at ", summary_speed_text(b.speed), ".", first_order);
}

const ResultTable<MillWhatToChange>& what_table() {
    using W = MillWhatToChange;
    static const ResultTable<W> table{
        "TandemWhatToChange",
        "What to change to run the mill faster (docs/model.md §13.6): the advised mill speed's "
        "derivatives at the binding limit by the implicit function theorem, ranked by the speed "
        "a typical step gains.",
        {
            {"binding_limit", "The limit the derivatives are of; null when none binds.",
             speed_limit_kind_schema(true),
             [](const W& w) { return speed_limit_kind_json(w.sensitivity.binding.kind); }},
            {"binding_stand",
             "Its stand, from 1 (for chatter the stand that moves in the crossing); null "
             "without a binding limit.",
             stand_number_schema(true),
             [](const W& w) {
                 return w.sensitivity.binding.kind ? stand_number(w.sensitivity.stand)
                                                   : json(nullptr);
             }},
            {"crossing",
             "For chatter, the critical speed that binds (frozen, delay_independent, "
             "nominal_delay), whose margin is differentiated; null otherwise.",
             enum_schema({"frozen", "delay_independent", "nominal_delay"}, true),
             [](const W& w) {
                 return w.sensitivity.crossing ? json(core::to_string(*w.sensitivity.crossing))
                                               : json(nullptr);
             }},
            {"crossing_speed_m_per_s",
             "Where its margin crosses zero: the limit's end, or the critical speed for chatter; "
             "null without derivatives.",
             number_schema(units::metre_per_second),
             [](const W& w) {
                 const core::BindingSensitivity& b = w.sensitivity.binding;
                 return b.ok ? json(b.speed) : json(nullptr);
             }},
            {"note", "What the figures mean here, for people.", string_schema(),
             [](const W& w) { return json(note(w)); }},
            {"changes", "One row per field of options.changes, the largest gain first.",
             array_schema(ref_schema("TandemSpeedLimitChange")),
             [](const W& w) {
                 json rows = json::array();
                 for (const Row& row : rows_of(w)) rows.push_back(row_table().write(row));
                 return rows;
             }},
        }};
    return table;
}

}  // namespace tandem_change_detail

namespace change_detail = tandem_change_detail;

std::string mill_given_field_message(std::string_view path, int stand, int stands) {
    for (const MillOwnedField& owned : mill_owned_stand_fields()) {
        if (path == owned.stand_path ||
            (path.starts_with(owned.stand_path) && path[owned.stand_path.size()] == '/')) {
            const std::string mill_pointer =
                stand >= 0 && stands > 0 ? tandem_pointer_of_stand_field(path, stand, stands)
                                         : std::string(owned.given_by);
            return concat(quoted_for_message(path), " is given to a stand by the mill: change ",
                          mill_pointer.empty() ? std::string(owned.given_by) : mill_pointer);
        }
    }
    return "";
}

std::optional<MillChangeField> find_mill_change_field(std::string_view path, int stands,
                                                      std::string& why, std::string& expected) {
    expected = std::string(change_detail::forms);
    std::string_view rest;
    int stand = -1;
    if (path.starts_with(change_detail::stands_prefix)) {
        const std::string_view after = path.substr(change_detail::stands_prefix.size());
        const std::size_t slash = after.find('/');
        const int count = stands > 0 ? stands : core::max_mill_stands;
        const std::optional<int> index =
            slash == std::string_view::npos
                ? std::nullopt
                : change_detail::read_index(after.substr(0, slash), count);
        if (!index) {
            why = concat(quoted_for_message(path),
                         " names no stand's field: /stands/{i}/... with i "
                         "from 0 to ",
                         std::to_string(count - 1));
            return std::nullopt;
        }
        stand = *index;
        rest = after.substr(slash);
    } else if (path.starts_with(change_detail::defaults_prefix)) {
        rest = path.substr(change_detail::defaults_prefix.size() - 1);
    } else {
        return change_detail::mill_field(path, stands, why);
    }
    const ScenarioField* field = change_detail::stand_scenario_number(rest, stand, stands, why);
    if (field == nullptr) return std::nullopt;
    return change_detail::stand_field(std::string(path), field, stand);
}

std::vector<MillChangeField> default_mill_change_fields(int stands) {
    std::vector<std::pair<std::string, double>> typical;  // in the fields' units
    const auto index = [](int i) { return std::to_string(i); };
    typical.emplace_back("/entry/tension_MPa", 5.0);
    for (int i = 0; i + 1 < stands; ++i)
        typical.emplace_back("/spans/tension_MPa/" + index(i), 5.0);
    typical.emplace_back("/exit/tension_MPa", 5.0);
    for (int i = 0; i + 1 < stands; ++i)
        typical.emplace_back("/exit_thickness_mm/" + index(i), 0.02);
    for (int i = 0; i < stands; ++i) {
        const std::string stand = "/stands/" + index(i);
        typical.emplace_back(stand + "/lubricant/viscosity_Pa_s", 0.0001);
        typical.emplace_back(stand + "/roughness/roll_rq_um", 0.1);
        typical.emplace_back(stand + "/rolls/radius_mm", 10.0);
    }
    std::vector<MillChangeField> out;
    for (const auto& [path, step] : typical) {
        std::string why, expected;
        std::optional<MillChangeField> field = find_mill_change_field(path, stands, why, expected);
        if (!field) continue;
        field->step = to_si(step, field->unit);
        out.push_back(std::move(*field));
    }
    return out;
}

void read_mill_changes(const nlohmann::json& list, const std::string& pointer, int stands,
                       std::vector<MillChangeField>& out, FieldErrors& errors) {
    if (!list.is_array() || list.size() > static_cast<std::size_t>(max_mill_change_fields)) {
        errors.add({pointer,
                    concat("must be an array of at most ", std::to_string(max_mill_change_fields),
                           " fields of the tandem document with their typical steps, e.g. "
                           "[{\"field\": \"/spans/tension_MPa/0\", \"step\": 5}]"),
                    concat("[0, ", std::to_string(max_mill_change_fields), "] items"),
                    std::nullopt});
        return;
    }
    std::vector<MillChangeField> read;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string at = concat(pointer, "/", std::to_string(i));
        const OptionsReader reader(list[i], at, change_detail::change_members, errors);
        if (!reader.is_object()) continue;
        const nlohmann::json* path = reader.find("field");
        if (path == nullptr) {
            errors.add({reader.at("field"),
                        "required: the JSON pointer of a number of the tandem document, e.g. "
                        "\"/spans/tension_MPa/0\"",
                        std::string(change_detail::forms), std::nullopt});
            continue;
        }
        const std::optional<std::string> text = read_string(*path, reader.at("field"), errors);
        if (!text) continue;
        std::string why, expected;
        std::optional<MillChangeField> field = find_mill_change_field(*text, stands, why, expected);
        if (!field) {
            errors.add({reader.at("field"), why, expected, std::nullopt});
            continue;
        }
        for (const MillChangeField& earlier : read)
            if (earlier.path == field->path)
                errors.add({reader.at("field"), concat(field->path, " is listed twice"),
                            std::nullopt, std::nullopt});
        const Interval steps = open_closed(0.0, field->range.max - field->range.min);
        if (reader.find("step") == nullptr) {
            errors.add({reader.at("step"),
                        concat("required: a typical step of the field, in its unit (",
                               field->unit.code, ")"),
                        steps.text(), std::string(field->unit.code)});
        } else if (reader.number("step", field->unit, steps, field->step)) {
            read.push_back(std::move(*field));
        }
    }
    out = std::move(read);
}

nlohmann::json mill_changes_json(const std::vector<MillChangeField>& changes) {
    nlohmann::json out = nlohmann::json::array();
    for (const MillChangeField& c : changes)
        out.push_back({{"field", c.path}, {"step", echo(c.step, c.unit)}});
    return out;
}

nlohmann::json mill_what_to_change_json(const MillWhatToChange& what) {
    return change_detail::what_table().write(what);
}

std::vector<ResultSchema> mill_what_to_change_schemas() {
    return {result_schema(change_detail::row_table()), result_schema(change_detail::what_table())};
}

}  // namespace rollgap::api
