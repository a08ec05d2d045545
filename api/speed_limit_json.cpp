// Reading the speed-limit analysis' options (the plant's limits, the posterior) and writing its
// result (api/speed_limit_json.h; docs/model.md §13).
#include "api/speed_limit_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

#include <Eigen/Eigenvalues>

#include "api/calibration_json.h"
#include "api/posterior_json.h"
#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/stability_json.h"
#include "api/text.h"
#include "api/units.h"

namespace rollgap::api {
namespace {

using std::string_view_literals::operator""sv;

constexpr std::string_view posterior_name = "posterior";
constexpr std::string_view changes_name = "changes";
constexpr std::array<std::string_view, 2> change_members{"field"sv, "step"sv};
// The options object's members: the search's, the limits', the posterior's.
const std::vector<std::string_view>& option_members() {
    static const std::vector<std::string_view> members = [] {
        std::vector<std::string_view> out(critical_speed_search_members().begin(),
                                          critical_speed_search_members().end());
        for (const OptionId id :
             {OptionId::max_roll_force, OptionId::max_torque, OptionId::max_power,
              OptionId::min_forward_slip, OptionId::chatter_limit, OptionId::chatter_margin,
              OptionId::confidence, OptionId::samples, OptionId::seed, OptionId::what_to_change})
            out.push_back(option_name(id));
        out.push_back(posterior_name);
        out.push_back(changes_name);
        return out;
    }();
    return members;
}

void read_limit(const OptionsReader& reader, OptionId id, std::optional<double>& target) {
    double value = 0.0;
    if (reader.read(id, value)) target = value;
}

// The fields to differentiate: number fields of the scenario other than the speed, each with a
// step > 0 no wider than its range, none twice.
void read_changes(const nlohmann::json& list, const std::string& pointer,
                  std::vector<ChangeField>& out, FieldErrors& errors) {
    if (!list.is_array() || list.size() > static_cast<std::size_t>(max_change_fields)) {
        errors.add({pointer,
                    concat("must be an array of at most ", std::to_string(max_change_fields),
                           " fields with their typical steps, e.g. [{\"field\": "
                           "\"/strip/reduction\", \"step\": 0.01}]"),
                    concat("[0, ", std::to_string(max_change_fields), "] items"), std::nullopt});
        return;
    }
    std::vector<ChangeField> read;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string at = concat(pointer, "/", std::to_string(i));
        const OptionsReader reader(list[i], at, change_members, errors);
        if (!reader.is_object()) continue;
        const ScenarioField* field =
            read_fitted_field(reader.find("field"), reader.at("field"), errors);
        if (field == nullptr) continue;
        if (field->path == "/rolls/speed_m_per_s") {
            errors.add({reader.at("field"),
                        "the roll speed is what the speed limit answers, not a change to it",
                        std::nullopt, std::nullopt});
            continue;
        }
        for (const ChangeField& earlier : read) {
            if (earlier.field == field)
                errors.add({reader.at("field"), concat(field->path, " is listed twice"),
                            std::nullopt, std::nullopt});
        }
        const Interval steps = open_closed(0.0, field->range.max - field->range.min);
        double step = 0.0;
        if (reader.find("step") == nullptr) {
            errors.add({reader.at("step"),
                        concat("required: a typical step of the field, in its unit (",
                               field->unit.code, ")"),
                        steps.text(), std::string(field->unit.code)});
        } else if (reader.number("step", field->unit, steps, step)) {
            read.push_back({field, step});
        }
    }
    out = std::move(read);
}

nlohmann::json changes_json(const std::vector<ChangeField>& changes) {
    nlohmann::json out = nlohmann::json::array();
    for (const ChangeField& c : changes)
        out.push_back({{"field", c.field->path}, {"step", echo(c.step, c.field->unit)}});
    return out;
}

// --- the result ---------------------------------------------------------------------------

// A limit's unit as the options write it, and its value converted.
Unit limit_unit(core::SpeedLimitKind kind) {
    switch (kind) {
        case core::SpeedLimitKind::chatter: return units::metre_per_second;
        case core::SpeedLimitKind::force: return units::kilonewton;
        case core::SpeedLimitKind::torque: return units::kilonewton_metre;
        case core::SpeedLimitKind::power: return units::kilowatt;
        default: return units::one;
    }
}

nlohmann::json finite_or_null(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json optional_speed(const std::optional<double>& speed) {
    return speed ? nlohmann::json(*speed) : nlohmann::json(nullptr);
}

nlohmann::json kind_or_null(const std::optional<core::SpeedLimitKind>& kind) {
    return speed_limit_kind_json(kind);
}

nlohmann::json kind_schema(bool nullable) { return speed_limit_kind_schema(nullable); }

}  // namespace

nlohmann::json speed_limit_kind_json(const std::optional<core::SpeedLimitKind>& kind) {
    return kind ? nlohmann::json(core::to_string(*kind)) : nlohmann::json(nullptr);
}

nlohmann::json speed_limit_kind_schema(bool nullable) {
    return enum_schema({"chatter", "force", "torque", "power", "skid", "steady_state"}, nullable);
}

std::vector<Member<core::LimitAnswer>> speed_limit_check_members() {
    return {
        {"limit", "Which limit: chatter, force, torque, power, skid or steady_state.",
         kind_schema(false),
         [](const core::LimitAnswer& a) { return nlohmann::json(core::to_string(a.kind)); }},
        {"unit",
         "The unit of value and at_operating: kN (force), kN.m (torque per work roll), kW "
         "(power), 1 (forward slip), m/s (chatter: the limit speed and the operating speed).",
         string_schema(),
         [](const core::LimitAnswer& a) { return nlohmann::json(limit_unit(a.kind).code); }},
        {"value",
         "The limit: the plant's value; for chatter the limit speed (V_c - z sigma)(1 - "
         "margin); null for steady_state, and for chatter when the stand chatters at the "
         "lowest speed of the range.",
         number_schema(units::one),
         [](const core::LimitAnswer& a) {
             if (a.kind == core::SpeedLimitKind::steady_state || a.limit < 0.0)
                 return nlohmann::json(nullptr);
             return nlohmann::json(from_si(a.limit, limit_unit(a.kind)));
         }},
        {"at_operating",
         "The figure at the operating speed (the roll force, torque, power, forward slip; "
         "chatter: the operating speed); null without a steady state there.",
         number_schema(units::one),
         [](const core::LimitAnswer& a) {
             if (a.kind == core::SpeedLimitKind::steady_state) return nlohmann::json(nullptr);
             if (a.kind != core::SpeedLimitKind::chatter && !std::isfinite(a.utilisation))
                 return nlohmann::json(nullptr);
             return nlohmann::json(from_si(a.at_operating, limit_unit(a.kind)));
         }},
        {"utilisation",
         "How much of the limit the operating speed uses: at_operating / value (skid: value / "
         "at_operating, null where the forward slip is not positive); 0.62 reads \"running at "
         "62 % of the limit\", above 1 the limit is exceeded.",
         number_schema(units::one),
         [](const core::LimitAnswer& a) {
             if (a.kind == core::SpeedLimitKind::skid && !(a.at_operating > 0.0))
                 return nlohmann::json(nullptr);
             return finite_or_null(a.utilisation);
         }},
        {"met_at_operating", "Whether the operating speed meets this limit.", boolean_schema(),
         [](const core::LimitAnswer& a) { return nlohmann::json(a.met_at_operating); }},
        {"lower_speed_m_per_s",
         "Below this speed the limit is violated; null if it holds down to the range's "
         "lowest speed.",
         number_schema(units::metre_per_second),
         [](const core::LimitAnswer& a) { return optional_speed(a.lower_speed); }},
        {"upper_speed_m_per_s",
         "Above this speed the limit is violated; null if it holds up to the range's "
         "highest speed.",
         number_schema(units::metre_per_second),
         [](const core::LimitAnswer& a) { return optional_speed(a.upper_speed); }},
        {"lower_speed_sd_m_per_s",
         "The standard deviation of lower_speed_m_per_s from the scenario's calibration "
         "posterior (linear, docs/model.md §13.2); the window takes the end at lower + z sd. "
         "Null without a posterior or a lower end.",
         number_schema(units::metre_per_second),
         [](const core::LimitAnswer& a) { return optional_speed(a.lower_speed_sd); }},
        {"upper_speed_sd_m_per_s",
         "The same for upper_speed_m_per_s; the window takes the end at upper − z sd (the "
         "chatter limit's is in `uncertainty` and in its value already).",
         number_schema(units::metre_per_second),
         [](const core::LimitAnswer& a) { return optional_speed(a.upper_speed_sd); }},
    };
}

namespace {

const ResultTable<core::LimitAnswer>& limit_table() {
    static const ResultTable<core::LimitAnswer> table{
        "SpeedLimitCheck",
        "One checked limit: the plant's value, the figure at the operating speed and the speeds "
        "where the limit binds, in `unit`.",
        speed_limit_check_members()};
    return table;
}

struct ParameterRow {
    const ScenarioField* field;
    double value, standard_error, sensitivity;  // SI
};

const ResultTable<ParameterRow>& propagated_parameter_table() {
    static const ResultTable<ParameterRow> table{
        "PropagatedParameter",
        "One posterior parameter and what it contributes to the critical speed's uncertainty.",
        {
            {"field", "The scenario field's JSON pointer.", string_schema(),
             [](const ParameterRow& r) { return nlohmann::json(r.field->path); }},
            {"unit", "The field's unit (UCUM code): of value and standard_error.", string_schema(),
             [](const ParameterRow& r) { return nlohmann::json(r.field->unit.code); }},
            {"value", "The posterior mean, in the field's unit.", number_schema(units::one, false),
             [](const ParameterRow& r) { return nlohmann::json(from_si(r.value, r.field->unit)); }},
            {"standard_error", "The posterior standard deviation, in the field's unit.",
             number_schema(units::one, false),
             [](const ParameterRow& r) {
                 return nlohmann::json(from_si(r.standard_error, r.field->unit));
             }},
            {"critical_speed_change_m_per_s",
             "dV_c/dx times the standard error: the critical speed's change for one standard "
             "error of this field (central differences at ± one standard error).",
             number_schema(units::metre_per_second),
             [](const ParameterRow& r) {
                 return finite_or_null(r.sensitivity * r.standard_error);
             }},
        }};
    return table;
}

const ResultTable<core::Propagated>& sampled_table() {
    static const ResultTable<core::Propagated> table{
        "SampledCriticalSpeed",
        "The critical speed at seeded draws from the posterior: the check on the linear "
        "propagation.",
        {
            {"samples", "Draws with a critical speed.", integer_schema(),
             [](const core::Propagated& p) { return nlohmann::json(p.samples); }},
            {"failed_samples", "Draws without one (no crossing in the range, no steady state).",
             integer_schema(),
             [](const core::Propagated& p) { return nlohmann::json(p.failed_samples); }},
            {"mean_m_per_s", "The draws' mean critical speed.",
             number_schema(units::metre_per_second),
             [](const core::Propagated& p) {
                 return p.ok ? nlohmann::json(p.value) : nlohmann::json(nullptr);
             }},
            {"standard_deviation_m_per_s", "The draws' standard deviation (n − 1).",
             number_schema(units::metre_per_second),
             [](const core::Propagated& p) {
                 return p.ok ? nlohmann::json(p.standard_deviation) : nlohmann::json(nullptr);
             }},
        }};
    return table;
}

const ResultTable<SpeedLimitUncertainty>& uncertainty_table() {
    static const ResultTable<SpeedLimitUncertainty> table{
        "CriticalSpeedUncertainty",
        "The critical speed's uncertainty from the scenario's calibration posterior "
        "(docs/model.md §13.2): linear, sigma² = g Σ gᵀ, and the one-sided lower bound the chatter "
        "limit is taken at.",
        {
            {"propagated",
             "Whether the critical speed exists at the posterior mean and at every difference "
             "point (else sigma is not known and the chatter limit is V_c itself).",
             boolean_schema(),
             [](const SpeedLimitUncertainty& u) { return nlohmann::json(u.linear.ok); }},
            {"critical_speed_m_per_s", "The critical speed at the posterior mean.",
             number_schema(units::metre_per_second),
             [](const SpeedLimitUncertainty& u) {
                 return u.linear.ok ? nlohmann::json(u.linear.value) : nlohmann::json(nullptr);
             }},
            {"standard_deviation_m_per_s", "sigma = sqrt(g Σ gᵀ).",
             number_schema(units::metre_per_second),
             [](const SpeedLimitUncertainty& u) {
                 return u.linear.ok ? nlohmann::json(u.linear.standard_deviation)
                                    : nlohmann::json(nullptr);
             }},
            {"confidence", "Of the one-sided lower bound.", number_schema(units::one, false),
             [](const SpeedLimitUncertainty& u) { return nlohmann::json(u.confidence); }},
            {"z", "The standard normal quantile at the confidence.",
             number_schema(units::one, false),
             [](const SpeedLimitUncertainty& u) {
                 return nlohmann::json(core::normal_quantile(u.confidence));
             }},
            {"lower_bound_m_per_s",
             "V_c - z sigma: the critical speed is above it with the confidence.",
             number_schema(units::metre_per_second),
             [](const SpeedLimitUncertainty& u) {
                 return u.linear.ok ? nlohmann::json(core::lower_bound(u.linear, u.confidence))
                                    : nlohmann::json(nullptr);
             }},
            {"parameters", "Each posterior parameter's share, in the posterior's order.",
             array_schema(ref_schema("PropagatedParameter")),
             [](const SpeedLimitUncertainty& u) {
                 nlohmann::json rows = nlohmann::json::array();
                 const Posterior& p = *u.posterior;
                 for (std::size_t i = 0; i < p.fields.size(); ++i) {
                     const auto j = static_cast<Eigen::Index>(i);
                     const double g = u.linear.ok ? u.linear.gradient(j) : std::nan("");
                     rows.push_back(propagated_parameter_table().write(
                         {p.fields[i], p.mean(j), p.standard_errors(j), g}));
                 }
                 return rows;
             }},
            {"sampled", "The draws' figures when options.samples > 0, else null.",
             ref_schema("SampledCriticalSpeed", true),
             [](const SpeedLimitUncertainty& u) {
                 if (!u.sampled) return nlohmann::json(nullptr);
                 nlohmann::json out = sampled_table().write(*u.sampled);
                 return out;
             }},
        }};
    return table;
}

struct ChangeRow {
    const ScenarioField* field;
    double value, step;                // SI
    std::optional<double> derivative;  // m/s per SI unit
    bool within_bounds = true;

    std::optional<double> gain() const {
        if (!derivative) return std::nullopt;
        return std::abs(*derivative * step);
    }
};

// The rows of what to change, ranked by the speed a typical step gains (rows without a
// derivative last, in the request's order).
std::vector<ChangeRow> change_rows(const WhatToChange& w) {
    std::vector<ChangeRow> rows;
    for (std::size_t j = 0; j < w.changes.size(); ++j) {
        const ChangeField& c = w.changes[j];
        core::Scenario copy = w.scenario;
        ChangeRow row{c.field, c.field->number(copy), c.step, w.sensitivity.derivatives[j]};
        if (row.derivative) {
            const double moved = row.value + (*row.derivative >= 0.0 ? c.step : -c.step);
            row.within_bounds = c.field->range.contains(from_si(moved, c.field->unit));
        }
        rows.push_back(row);
    }
    std::stable_sort(rows.begin(), rows.end(), [](const ChangeRow& a, const ChangeRow& b) {
        return a.gain().value_or(-1.0) > b.gain().value_or(-1.0);
    });
    return rows;
}

const ResultTable<ChangeRow>& change_table() {
    static const ResultTable<ChangeRow> table{
        "SpeedLimitChange",
        "One field a plant can set: how the advised speed moves with it, per unit and per "
        "typical step, at the binding limit.",
        {
            {"field", "The scenario field's JSON pointer.", string_schema(),
             [](const ChangeRow& r) { return nlohmann::json(r.field->path); }},
            {"unit", "The field's unit (UCUM code): of value and step.", string_schema(),
             [](const ChangeRow& r) { return nlohmann::json(r.field->unit.code); }},
            {"value", "The scenario's value.", number_schema(units::one, false),
             [](const ChangeRow& r) { return nlohmann::json(from_si(r.value, r.field->unit)); }},
            {"step", "The typical step (options.changes).", number_schema(units::one, false),
             [](const ChangeRow& r) { return nlohmann::json(from_si(r.step, r.field->unit)); }},
            {"advised_speed_change_m_per_s_per_unit",
             "d(advised speed)/d(field) in m/s per the field's unit; null where the model had no "
             "answer at a difference point.",
             number_schema(units::one),
             [](const ChangeRow& r) {
                 if (!r.derivative) return nlohmann::json(nullptr);
                 return nlohmann::json(*r.derivative * to_si(1.0, r.field->unit));
             }},
            {"speed_gain_m_per_s",
             "What one typical step in `direction` gains, to first order (the same limit still "
             "binding).",
             number_schema(units::metre_per_second),
             [](const ChangeRow& r) {
                 return r.gain() ? nlohmann::json(*r.gain()) : nlohmann::json(nullptr);
             }},
            {"direction", "raise or lower the field to gain speed; null without a derivative.",
             enum_schema({"raise", "lower"}, true),
             [](const ChangeRow& r) {
                 if (!r.derivative) return nlohmann::json(nullptr);
                 return nlohmann::json(*r.derivative >= 0.0 ? "raise" : "lower");
             }},
            {"within_bounds", "Whether the step in that direction stays inside the field's bounds.",
             boolean_schema(), [](const ChangeRow& r) { return nlohmann::json(r.within_bounds); }},
        }};
    return table;
}

std::string change_note(const WhatToChange& w, double margin) {
    const core::BindingSensitivity& b = w.sensitivity;
    if (!b.kind)
        return "No limit binds below the range's highest speed: nothing to gain by a change.";
    if (*b.kind == core::SpeedLimitKind::steady_state)
        return "The bite loses its steady state above the advised speed: that edge has no margin "
               "to differentiate.";
    if (!b.ok) return "The binding limit's margin could not be differentiated there.";
    if (*b.kind == core::SpeedLimitKind::chatter)
        return concat("The chatter limit binds: a change moves the critical speed (",
                      summary_speed_text(b.speed), " here), and the advised speed by ",
                      format_number(1.0 - margin),
                      " of that (the margin held). First order: "
                      "a step large enough for another limit to bind gains less.");
    return concat("The ", core::to_string(*b.kind), " limit binds at ", summary_speed_text(b.speed),
                  ". First order: a step large enough for another limit to bind gains less.");
}

const ResultTable<SpeedLimitReport>& what_to_change_table() {
    static const ResultTable<SpeedLimitReport> table{
        "WhatToChange",
        "What to change to run faster (docs/model.md §13.4): the advised speed's derivatives "
        "at the binding limit by the implicit function theorem, ranked by the speed a typical "
        "step gains.",
        {
            {"binding_limit", "The limit the derivatives are of; null when none binds.",
             kind_schema(true),
             [](const SpeedLimitReport& r) {
                 return kind_or_null(r.what_to_change->sensitivity.kind);
             }},
            {"crossing_speed_m_per_s",
             "Where its margin crosses zero: the window's end, or the critical speed for "
             "chatter; null without derivatives.",
             number_schema(units::metre_per_second),
             [](const SpeedLimitReport& r) {
                 const core::BindingSensitivity& b = r.what_to_change->sensitivity;
                 return b.ok ? nlohmann::json(b.speed) : nlohmann::json(nullptr);
             }},
            {"note", "What the figures mean here, for people.", string_schema(),
             [](const SpeedLimitReport& r) {
                 return nlohmann::json(change_note(*r.what_to_change, r.limits.chatter_margin));
             }},
            {"changes", "One row per field of options.changes, the largest gain first.",
             array_schema(ref_schema("SpeedLimitChange")),
             [](const SpeedLimitReport& r) {
                 nlohmann::json rows = nlohmann::json::array();
                 for (const ChangeRow& row : change_rows(*r.what_to_change))
                     rows.push_back(change_table().write(row));
                 return rows;
             }},
        }};
    return table;
}

const ResultTable<SpeedLimitReport>& result_table() {
    static const ResultTable<SpeedLimitReport> table{
        "SpeedLimitResult",
        "The speeds the stand may run at under the plant's limits (docs/model.md §13): the "
        "permitted window around the operating speed, the limit binding at each end, every "
        "checked limit and the advised speed.",
        {
            {"status",
             "ok: a permitted window (the operating speed inside it or not); no_window: no speed "
             "in the range meets every checked limit; no_operating: the operating speed has no "
             "steady state and nothing else to start from.",
             enum_schema({"ok", "no_window", "no_operating"}),
             [](const SpeedLimitReport& r) {
                 return nlohmann::json(core::to_string(r.result.status));
             }},
            {"summary", "The answer in one sentence, for people.", string_schema(),
             [](const SpeedLimitReport& r) { return nlohmann::json(speed_limit_summary(r)); }},
            {"operating_speed_m_per_s", "The scenario's roll speed.",
             number_schema(units::metre_per_second, false),
             [](const SpeedLimitReport& r) { return nlohmann::json(r.result.operating_speed); }},
            {"advised_speed_m_per_s",
             "The highest permitted speed: the window's upper end, the chatter limit taken at "
             "its lower bound (V_c - z sigma)(1 - margin) and, with a posterior, every plant "
             "limit's upper end at its own (upper − z sd); null without a window.",
             number_schema(units::metre_per_second),
             [](const SpeedLimitReport& r) {
                 return r.result.status == core::SpeedLimitStatus::ok
                            ? nlohmann::json(r.result.advised_speed)
                            : nlohmann::json(nullptr);
             }},
            {"binding_limit",
             "The limit that sets the advised speed; null when it is the range's highest speed "
             "(speed_max_m_per_s).",
             kind_schema(true),
             [](const SpeedLimitReport& r) { return kind_or_null(r.result.binding_max); }},
            {"window_min_m_per_s", "The permitted window's lower end; null without a window.",
             number_schema(units::metre_per_second),
             [](const SpeedLimitReport& r) {
                 return r.result.status == core::SpeedLimitStatus::ok
                            ? nlohmann::json(r.result.window_min)
                            : nlohmann::json(nullptr);
             }},
            {"window_max_m_per_s", "The permitted window's upper end (the advised speed).",
             number_schema(units::metre_per_second),
             [](const SpeedLimitReport& r) {
                 return r.result.status == core::SpeedLimitStatus::ok
                            ? nlohmann::json(r.result.window_max)
                            : nlohmann::json(nullptr);
             }},
            {"binding_min",
             "The limit that sets the window's lower end (a force limit usually does: the force "
             "falls as the speed rises); null when it is the range's lowest speed.",
             kind_schema(true),
             [](const SpeedLimitReport& r) { return kind_or_null(r.result.binding_min); }},
            {"operating_permitted", "Whether the operating speed lies in the window.",
             boolean_schema(),
             [](const SpeedLimitReport& r) {
                 return nlohmann::json(r.result.operating_permitted);
             }},
            {"checked",
             "The limits checked: steady_state always, the others when the options give them "
             "(chatter unless chatter is false).",
             array_schema(kind_schema(false)),
             [](const SpeedLimitReport& r) {
                 nlohmann::json names = nlohmann::json::array();
                 for (const core::LimitAnswer& a : r.result.limits)
                     names.push_back(core::to_string(a.kind));
                 return names;
             }},
            {"limits", "Every checked limit, in the order of checked.",
             array_schema(ref_schema("SpeedLimitCheck")),
             [](const SpeedLimitReport& r) {
                 nlohmann::json rows = nlohmann::json::array();
                 for (const core::LimitAnswer& a : r.result.limits)
                     rows.push_back(limit_table().write(a));
                 return rows;
             }},
            {"critical_speed",
             "The critical-speed search behind the chatter limit (null when chatter is not "
             "checked).",
             ref_schema("CriticalSpeedSummary", true),
             [](const SpeedLimitReport& r) {
                 return r.limits.chatter ? critical_speed_summary_json(r.result.chatter)
                                         : nlohmann::json(nullptr);
             }},
            {"what_to_change",
             "What to change to run faster; null when options.what_to_change is false.",
             ref_schema("WhatToChange", true),
             [](const SpeedLimitReport& r) {
                 return r.what_to_change ? what_to_change_table().write(r)
                                         : nlohmann::json(nullptr);
             }},
            {"uncertainty",
             "The critical speed's uncertainty from options.posterior; null without one.",
             ref_schema("CriticalSpeedUncertainty", true),
             [](const SpeedLimitReport& r) {
                 return r.uncertainty ? uncertainty_table().write(*r.uncertainty)
                                      : nlohmann::json(nullptr);
             }},
        }};
    return table;
}

}  // namespace

std::string summary_percent_text(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, "%.0f %%", 100.0 * fraction);
    return text;
}

std::string summary_speed_text(double speed) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f m/s", speed);
    return text;
}

std::vector<ChangeField> default_change_fields() {
    // What a plant sets between coils, with a step it would take (in the fields' units).
    static const std::vector<std::pair<std::string_view, double>> typical{
        {"/tension/back/stress_MPa", 5.0}, {"/tension/front/stress_MPa", 5.0},
        {"/strip/reduction", 0.01},        {"/lubricant/viscosity_Pa_s", 0.0001},
        {"/roughness/roll_rq_um", 0.1},    {"/roughness/strip_rq_um", 0.1},
        {"/rolls/radius_mm", 10.0},
    };
    std::vector<ChangeField> out;
    for (const auto& [path, step] : typical) {
        const ScenarioField* field = find_scenario_field(path);
        if (field != nullptr) out.push_back({field, to_si(step, field->unit)});
    }
    return out;
}

SpeedLimitOptions speed_limit_options_from_json(const nlohmann::json& options,
                                                const std::string& pointer,
                                                const core::Scenario* valid_scenario,
                                                FieldErrors& errors) {
    SpeedLimitOptions out;
    const OptionsReader reader(options, pointer, option_members(), errors);
    read_critical_speed_search(reader, out.search);
    read_limit(reader, OptionId::max_roll_force, out.limits.max_force);
    read_limit(reader, OptionId::max_torque, out.limits.max_torque);
    read_limit(reader, OptionId::max_power, out.limits.max_power);
    read_limit(reader, OptionId::min_forward_slip, out.limits.min_forward_slip);
    reader.read(OptionId::chatter_limit, out.limits.chatter);
    reader.read(OptionId::chatter_margin, out.limits.chatter_margin);
    reader.read(OptionId::confidence, out.limits.confidence);
    reader.read(OptionId::samples, out.samples);
    reader.read(OptionId::seed, out.seed);
    reader.read(OptionId::what_to_change, out.what_to_change);
    if (const nlohmann::json* changes = reader.find(changes_name))
        read_changes(*changes, reader.at(changes_name), out.changes, errors);
    if (const nlohmann::json* posterior = reader.find(posterior_name)) {
        out.posterior =
            read_posterior(*posterior, reader.at(posterior_name), valid_scenario, errors);
    }
    if (out.samples > 0 && !out.posterior && !reader.failed(posterior_name)) {
        errors.add({reader.at(option_name(OptionId::samples)),
                    "draws need a posterior to draw from: give options.posterior (calibrate's "
                    "fitted parameters and correlation) or set samples to 0",
                    std::nullopt, std::nullopt});
    }
    if (out.samples > 0 && !out.limits.chatter && !reader.failed(option_name(OptionId::samples))) {
        errors.add({reader.at(option_name(OptionId::samples)),
                    "the draws check the critical speed's uncertainty, which is not used when "
                    "chatter is false: set samples to 0",
                    std::nullopt, std::nullopt});
    }
    return out;
}

nlohmann::json speed_limit_options_json(const SpeedLimitOptions& options) {
    nlohmann::json document = critical_speed_options_json(options.search);
    const core::PlantLimits& l = options.limits;
    if (l.max_force) put_option(document, OptionId::max_roll_force, *l.max_force);
    if (l.max_torque) put_option(document, OptionId::max_torque, *l.max_torque);
    if (l.max_power) put_option(document, OptionId::max_power, *l.max_power);
    if (l.min_forward_slip) put_option(document, OptionId::min_forward_slip, *l.min_forward_slip);
    put_option(document, OptionId::chatter_limit, l.chatter);
    put_option(document, OptionId::chatter_margin, l.chatter_margin);
    put_option(document, OptionId::confidence, l.confidence);
    put_option(document, OptionId::samples, options.samples);
    put_option(document, OptionId::seed, options.seed);
    put_option(document, OptionId::what_to_change, options.what_to_change);
    document[std::string(changes_name)] = changes_json(options.changes);
    document[std::string(posterior_name)] =
        options.posterior ? posterior_json(*options.posterior) : nlohmann::json(nullptr);
    return document;
}

std::string speed_limit_summary(const SpeedLimitReport& report) {
    const core::SpeedLimitResult& r = report.result;
    const std::string at = concat("runs at ", summary_speed_text(r.operating_speed));
    if (r.status == core::SpeedLimitStatus::no_operating)
        return concat("The stand has no steady state at ", summary_speed_text(r.operating_speed),
                      " and nowhere else to start from: no speed is permitted.");
    if (r.status == core::SpeedLimitStatus::no_window)
        return concat("The stand ", at,
                      "; no speed in the range meets every checked limit (see limits).");
    std::string binding = r.binding_max ? concat(core::to_string(*r.binding_max), " limit")
                                        : std::string("the range's highest speed");
    for (const core::LimitAnswer& a : r.limits) {
        if (r.binding_max && a.kind == *r.binding_max && std::isfinite(a.utilisation) &&
            a.kind == core::SpeedLimitKind::chatter) {
            binding = concat("its ", summary_speed_text(a.limit), " chatter limit");
            return concat("The stand ", at, ", ", summary_percent_text(a.utilisation), " of ",
                          binding, "; it may run at ", summary_speed_text(r.window_min), " to ",
                          summary_speed_text(r.window_max), ".");
        }
    }
    return concat("The stand ", at, (r.operating_permitted ? " (permitted)" : " (not permitted)"),
                  "; it may run at ", summary_speed_text(r.window_min), " to ",
                  summary_speed_text(r.window_max), ", the upper end set by ", binding, ".");
}

nlohmann::json speed_limit_result_json(const SpeedLimitReport& report) {
    return result_table().write(report);
}

std::vector<std::string> speed_limit_check_columns() { return limit_table().names(); }

nlohmann::json sampled_critical_speed_json(const core::Propagated& sampled) {
    return sampled_table().write(sampled);
}

std::vector<ResultSchema> speed_limit_result_schemas() {
    return {result_schema(limit_table()),
            result_schema(change_table()),
            result_schema(what_to_change_table()),
            result_schema(propagated_parameter_table()),
            result_schema(sampled_table()),
            result_schema(uncertainty_table()),
            result_schema(critical_speed_summary_table()),
            result_schema(result_table())};
}

}  // namespace rollgap::api
