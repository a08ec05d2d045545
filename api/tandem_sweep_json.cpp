#include "api/tandem_sweep_json.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "api/chatter_json.h"
#include "api/json_pointer.h"
#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/scenario_schema.h"
#include "api/stability_json.h"
#include "api/sweep_json.h"
#include "api/tandem_json.h"
#include "api/tandem_result_json.h"
#include "api/tandem_schema.h"
#include "api/text.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_stability.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside the stand's sweep and the tandem
// answer, whose anonymous helpers have the same names.
namespace tandem_sweep_detail {

using nlohmann::json;
using namespace units;

constexpr std::string_view parameter_name = "parameter";
constexpr std::string_view quantity_name = "quantity";
constexpr std::string_view critical_speed_member = "critical_speed";
constexpr std::array<std::string_view, 5> sweep_members{parameter_name, "values", "range",
                                                        quantity_name, critical_speed_member};
constexpr std::array<std::string_view, 2> quantities{"critical_speed", "stability"};

// The reference tokens of a JSON pointer (RFC 6901), unescaped; "" gives none.
std::vector<std::string> pointer_tokens(std::string_view path) {
    std::vector<std::string> tokens;
    if (path.empty() || path.front() != '/') return tokens;
    std::string token;
    for (std::size_t k = 1; k <= path.size(); ++k) {
        if (k == path.size() || path[k] == '/') {
            tokens.push_back(std::move(token));
            token.clear();
        } else if (path[k] == '~' && k + 1 < path.size() &&
                   (path[k + 1] == '0' || path[k + 1] == '1')) {
            token.push_back(path[k + 1] == '1' ? '/' : '~');
            ++k;
        } else {
            token.push_back(path[k]);
        }
    }
    return tokens;
}

// The unit of the number a pointer into the tandem document names: a mill field's (a list's
// element or the whole list), or a stand's scenario field's under /stands/<i>.
std::optional<Unit> unit_of(std::string_view path) {
    const std::vector<std::string> tokens = pointer_tokens(path);
    if (tokens.empty()) return std::nullopt;
    if (tokens.front() == stands_member) {
        if (tokens.size() < 3) return std::nullopt;
        std::string field;
        for (std::size_t i = 2; i < tokens.size(); ++i) field += concat("/", tokens[i]);
        const ScenarioField* found = find_scenario_field(field);
        if (found == nullptr ||
            (found->kind != FieldKind::number && found->kind != FieldKind::integer))
            return std::nullopt;
        return found->unit;
    }
    std::string field;
    for (const std::string& token : tokens) {
        if (!token.empty() && token.find_first_not_of("0123456789") == std::string::npos) break;
        field += concat("/", token);
    }
    const TandemField* found = find_tandem_field(field);
    if (found == nullptr || found->kind == TandemFieldKind::choice) return std::nullopt;
    return found->unit;
}

// The parameter: a string pointer that names a number or a list of numbers in `document` (the
// request's resolved mill; nullptr when the mill is invalid: only the shape is checked).
std::optional<std::string> read_parameter(const OptionsReader& reader, const json* document,
                                          Unit& unit) {
    const std::string pointer = reader.at(parameter_name);
    const json* value = reader.find(parameter_name);
    if (value == nullptr) {
        reader.errors().add({pointer,
                             "required: the JSON pointer of a number of the tandem document "
                             "(GET /v1/mills/default), e.g. \"/spans/length_m/0\"",
                             std::nullopt, std::nullopt});
        return std::nullopt;
    }
    const auto path = read_string(*value, pointer, reader.errors());
    if (!path) return std::nullopt;
    const auto refuse = [&](std::string why) {
        reader.errors().add(
            {pointer,
             concat(quoted_for_message(*path), " ", why,
                    ": give a JSON pointer into the tandem document as GET /v1/mills/default "
                    "shows it (a number, or a list of numbers to set whole), e.g. "
                    "\"/spans/tension_MPa/1\", \"/stands/2/lubricant/viscosity_Pa_s\""),
             std::nullopt, std::nullopt});
        return std::nullopt;
    };
    const auto found_unit = unit_of(*path);
    if (!found_unit) return refuse("names no numeric field of the tandem document");
    if (path->starts_with("/stand_defaults"))
        return refuse("is a patch, not a value of the resolved mill (send the stands instead)");
    if (document != nullptr) {
        json::json_pointer location;
        try {
            location = json::json_pointer(*path);
        } catch (const json::exception&) {
            return refuse("is not a JSON pointer");
        }
        if (!document->contains(location)) {
            // A stand's field that the mill gives it (its thickness, tension, speed, ...) is not
            // in the stand's document: name the mill's field that sets it.
            const std::vector<std::string> tokens = pointer_tokens(*path);
            if (tokens.size() >= 3 && tokens.front() == stands_member &&
                document->contains("stands")) {
                std::string field;
                for (std::size_t i = 2; i < tokens.size(); ++i) field += concat("/", tokens[i]);
                const int stand = std::atoi(tokens[1].c_str());
                const int count = static_cast<int>((*document)["stands"].size());
                if (stand >= 0 && stand < count) {
                    const std::string given = tandem_pointer_of_stand_field(field, stand, count);
                    if (!given.empty())
                        return refuse(concat("is given to the stand by the mill: sweep ",
                                             quoted_for_message(given), " instead"));
                }
            }
            return refuse("is not in this mill's document");
        }
        const json& target = (*document)[location];
        const bool numbers =
            target.is_array() && !target.empty() &&
            std::all_of(target.begin(), target.end(), [](const json& v) { return v.is_number(); });
        if (!target.is_number() && !numbers)
            return refuse("is not a number (nor a list of numbers) in this mill's document");
    }
    unit = *found_unit;
    return *path;
}

// Writes each point into the resolved document and reads it back as a request's tandem is.
void build_mills(const std::vector<SweepPoint>& points, const core::Mill& mill,
                 TandemSweepPlan& plan, FieldErrors& errors) {
    const json base = resolved_tandem_json(mill);
    const json::json_pointer location(plan.parameter);
    const std::string field_pointer = concat("/tandem", plan.parameter);
    bool interior_reported = false;
    for (const SweepPoint& point : points) {
        if (!point.value.is_number()) {
            errors.add({point.pointer,
                        concat("must be a number, got ", json_type_name(point.value)), std::nullopt,
                        std::nullopt});
            continue;
        }
        json document = base;
        json& target = document[location];
        if (target.is_array()) {
            for (json& element : target) element = point.value;  // a list set whole
        } else {
            target = point.value;
        }
        FieldErrors point_errors;
        core::Mill swept = mill_from_json(document, "/tandem", point_errors);
        if (point_errors.empty()) {
            plan.values.push_back(point.value.get<double>());
            plan.mills.push_back(std::move(swept));
            continue;
        }
        if (point.range_index) {
            if (interior_reported) continue;
            interior_reported = true;
        }
        const std::string where =
            point.range_index
                ? concat("point ", std::to_string(*point.range_index), " of the range (",
                         format_number(point.value.get<double>()), "): ")
                : std::string();
        for (const FieldError& error : point_errors.reported()) {
            if (error.pointer == field_pointer || error.pointer.starts_with(field_pointer + "/")) {
                errors.add({point.pointer, concat(where, error.detail), error.bound, error.unit});
            } else {
                // A rule of the mill as a whole: the value is fine for the field, not with the
                // rest (a schedule that no longer falls, a tension above a stand's flow stress).
                errors.add({point.pointer,
                            concat(where, "with ", plan.parameter, " = ",
                                   format_number(point.value.get<double>()),
                                   " the mill is invalid at ", error.pointer, ": ", error.detail),
                            std::nullopt, std::nullopt});
            }
        }
    }
}

// ---- the points ------------------------------------------------------------------------------

json speed_or_null(const core::MillCrossing& c) {
    return c.status == core::CriticalSpeedStatus::found ? quantity_json(c.speed, metre_per_second)
                                                        : json(nullptr);
}

const core::MillCrossing* headline_of(const core::MillCriticalSpeeds& s) {
    switch (s.headline) {
        case 0: return &s.frozen;
        case 1: return &s.delay_independent;
        case 2: return &s.nominal_delay;
        default: return nullptr;
    }
}

const ResultTable<core::MillCriticalSpeeds>& critical_point_table() {
    using S = core::MillCriticalSpeeds;
    static const ResultTable<S> table{
        "TandemSweepCriticalSpeedPoint",
        "The mill's critical speeds at one value (docs/model.md §12.7): the headline and the "
        "three speeds.",
        {
            {"status",
             "found (a headline); outside_range (crossings found, none inside the model's range: "
             "see the three speeds); otherwise the frozen search's status: stable_in_range, "
             "unstable_at_lower_bound, no_steady_state.",
             enum_schema({"found", "outside_range", "stable_in_range", "unstable_at_lower_bound",
                          "no_steady_state", "cancelled"}),
             [](const S& s) {
                 if (s.headline >= 0) return json("found");
                 if (!s.outside_range_below.empty()) return json("outside_range");
                 return json(core::to_string(s.frozen.status));
             }},
            {"critical_speed_m_per_s", "The headline: the lowest crossing inside the range.",
             number_schema(metre_per_second),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? quantity_json(h->speed, metre_per_second) : json(nullptr);
             }},
            {"kind", "Which speed is the headline.",
             enum_schema({"frozen", "delay_independent", "nominal_delay"}, true),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? json(core::to_string(h->kind)) : json(nullptr);
             }},
            {"frequency_Hz", "The headline crossing's frequency.", number_schema(hertz),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? quantity_json(h->frequency_Hz, hertz) : json(nullptr);
             }},
            {"moving_stand", "The stand the headline crossing moves most (1-based).",
             stand_number_schema(true),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? stand_number(h->moving_stand) : json(nullptr);
             }},
            {"feeding_stand", "The stand whose bite feeds the headline crossing (1-based).",
             stand_number_schema(true),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? stand_number(h->feeding_stand) : json(nullptr);
             }},
            {"chatter_band", std::string_view(chatter_band_text), chatter_type_schema(true),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? json(core::to_string(h->band)) : json(nullptr);
             }},
            {"frozen_m_per_s", "The frozen critical speed (the tension path alone), or null.",
             number_schema(metre_per_second), [](const S& s) { return speed_or_null(s.frozen); }},
            {"delay_independent_m_per_s", "The delay-independent critical speed, or null.",
             number_schema(metre_per_second),
             [](const S& s) { return speed_or_null(s.delay_independent); }},
            {"nominal_delay_m_per_s", "The nominal-delay critical speed (in the band), or null.",
             number_schema(metre_per_second),
             [](const S& s) { return speed_or_null(s.nominal_delay); }},
        }};
    return table;
}

struct StabilityPoint {
    core::MillSpeedStability at;
    core::MillRootDescription root;
};

const ResultTable<StabilityPoint>& stability_point_table() {
    using P = StabilityPoint;
    static const ResultTable<P> table{
        "TandemSweepStabilityPoint",
        "The mill at its speed at one value (docs/model.md §12.5-12.6).",
        {
            {"status",
             "ok; no_steady_state (the schedule has none at this value); failed (the root count "
             "did not close).",
             enum_schema({"ok", "no_steady_state", "failed"}),
             [](const P& p) {
                 if (p.at.steady.status != core::MillSteadyStatus::ok)
                     return json("no_steady_state");
                 return json(p.at.nominal.ok ? "ok" : "failed");
             }},
            {"stable", "No root with the nominal delays right of the axis; null when not counted.",
             boolean_schema(true),
             [](const P& p) {
                 return p.at.nominal.ok ? json(p.at.nominal_stable) : json(nullptr);
             }},
            {"growth_rate_per_s", "The rightmost root's real part (positive: chatter grows).",
             number_schema(per_second),
             [](const P& p) {
                 return p.root.found ? quantity_json(p.root.s.real(), per_second) : json(nullptr);
             }},
            {"frequency_Hz", "The rightmost root's frequency.", number_schema(hertz),
             [](const P& p) {
                 return p.root.found ? quantity_json(p.root.described.frequency_Hz, hertz)
                                     : json(nullptr);
             }},
            {"moving_stand", "The stand the rightmost root moves most (1-based).",
             stand_number_schema(true),
             [](const P& p) {
                 return p.root.found ? stand_number(p.root.described.moving_stand) : json(nullptr);
             }},
            {"feeding_stand", "The stand whose bite feeds the rightmost root (1-based).",
             stand_number_schema(true),
             [](const P& p) {
                 return p.root.found ? stand_number(p.root.described.feeding_stand) : json(nullptr);
             }},
            {"in_model_range", "Whether the rightmost root lies inside the model's range.",
             boolean_schema(true),
             [](const P& p) {
                 return p.root.found ? json(p.root.described.validity.valid()) : json(nullptr);
             }},
            {"regenerative_margin",
             "rho: the peak of the structured gain of the transport loop (< 1 with frozen_stable: "
             "stable for every set of delays); null when A0 is unstable.",
             number_schema(one),
             [](const P& p) {
                 return p.at.margin.ok && p.at.margin.frozen_stable
                            ? quantity_json(p.at.margin.margin, one)
                            : json(nullptr);
             }},
            {"frozen_stable", "A0 is stable: the tension path alone does not chatter.",
             boolean_schema(), [](const P& p) { return json(p.at.frozen.stable); }},
            {"roots_in_band",
             "Roots right of the axis inside the model's band (what the nominal-delay critical "
             "speed counts); null when not counted.",
             integer_schema(true),
             [](const P& p) {
                 return p.root.band_count >= 0 ? json(p.root.band_count) : json(nullptr);
             }},
            {"roots_right_of_axis", "Roots with the nominal delays right of the axis (any band).",
             integer_schema(true),
             [](const P& p) { return p.at.nominal.ok ? json(p.at.nominal.count) : json(nullptr); }},
        }};
    return table;
}

struct SweepOutput {
    const TandemSweepPlan* plan = nullptr;
    json points;
};

const ResultTable<SweepOutput>& result_table() {
    static const ResultTable<SweepOutput> table{
        "TandemSweepResult",
        "A mill sweep: one value of the tandem document over the values, the mill at each.",
        {
            {"parameter", "The swept pointer into the tandem document.", string_schema(),
             [](const SweepOutput& o) { return json(o.plan->parameter); }},
            {"unit", "The swept value's unit (UCUM).", string_schema(),
             [](const SweepOutput& o) { return json(o.plan->unit.code); }},
            {"value_name", "The member under which each point carries its value.", string_schema(),
             [](const SweepOutput& o) { return json(sweep_value_name(o.plan->unit)); }},
            {"quantity", "What each point holds.", enum_schema({"critical_speed", "stability"}),
             [](const SweepOutput& o) {
                 return json(o.plan->quantity == TandemSweepQuantity::stability ? "stability"
                                                                                : "critical_speed");
             }},
            {"points", "One per value, in the order of options.values or the range.",
             array_schema({{"oneOf", json::array({ref_schema("TandemSweepCriticalSpeedPoint"),
                                                  ref_schema("TandemSweepStabilityPoint")})}}),
             [](const SweepOutput& o) { return o.points; }},
        }};
    return table;
}

}  // namespace tandem_sweep_detail

TandemSweepPlan tandem_sweep_plan_from_json(const nlohmann::json& options,
                                            const std::string& pointer,
                                            const core::Mill* valid_mill, FieldErrors& errors) {
    TandemSweepPlan plan;
    const OptionsReader reader(options, pointer, tandem_sweep_detail::sweep_members, errors);
    if (!reader.is_object()) return plan;
    const nlohmann::json document =
        valid_mill != nullptr ? resolved_tandem_json(*valid_mill) : nlohmann::json();
    const auto parameter = tandem_sweep_detail::read_parameter(
        reader, valid_mill != nullptr ? &document : nullptr, plan.unit);

    std::string quantity = "critical_speed";
    bool quantity_valid = true;
    if (const nlohmann::json* value = reader.find(tandem_sweep_detail::quantity_name)) {
        if (auto choice = read_choice(*value, reader.at(tandem_sweep_detail::quantity_name),
                                      tandem_sweep_detail::quantities, errors)) {
            quantity = std::move(*choice);
        } else {
            quantity_valid = false;
        }
    }
    plan.quantity = quantity == "stability" ? TandemSweepQuantity::stability
                                            : TandemSweepQuantity::critical_speed;
    nlohmann::json echo_values;
    const auto points = read_sweep_points(reader, echo_values, max_tandem_sweep_points);

    nlohmann::json quantity_options;
    if (quantity_valid && plan.quantity == TandemSweepQuantity::critical_speed) {
        const nlohmann::json* search = reader.find(tandem_sweep_detail::critical_speed_member);
        plan.critical_speed = critical_speed_options_from_json(
            search != nullptr ? *search : nlohmann::json::object(),
            reader.at(tandem_sweep_detail::critical_speed_member), errors);
        quantity_options = critical_speed_options_json(plan.critical_speed);
    } else if (quantity_valid &&
               reader.find(tandem_sweep_detail::critical_speed_member) != nullptr) {
        errors.add({reader.at(tandem_sweep_detail::critical_speed_member),
                    "applies to quantity 'critical_speed' only; this sweep's quantity is "
                    "'stability'",
                    std::nullopt, std::nullopt});
    }
    if (parameter) plan.parameter = *parameter;
    if (parameter && points && valid_mill != nullptr)
        tandem_sweep_detail::build_mills(*points, *valid_mill, plan, errors);

    plan.resolved_options = {
        {tandem_sweep_detail::parameter_name,
         parameter ? nlohmann::json(*parameter) : nlohmann::json(nullptr)},
        {tandem_sweep_detail::quantity_name, quantity},
    };
    if (echo_values.is_object()) plan.resolved_options.update(echo_values);
    if (plan.quantity == TandemSweepQuantity::critical_speed)
        plan.resolved_options[tandem_sweep_detail::critical_speed_member] =
            std::move(quantity_options);
    return plan;
}

nlohmann::json tandem_sweep_points_json(const TandemSweepPlan& plan, std::size_t first,
                                        std::size_t count, const core::Control& control) {
    const std::string key = sweep_value_name(plan.unit);
    nlohmann::json points = nlohmann::json::array();
    for (std::size_t i = first; i < first + count && i < plan.mills.size(); ++i) {
        if (control.should_stop()) break;  // the caller reports the cancellation
        const core::Mill& mill = plan.mills[i];
        nlohmann::json point;
        if (plan.quantity == TandemSweepQuantity::critical_speed) {
            // The point's own search reports no progress: the points do.
            point = tandem_sweep_detail::critical_point_table().write(core::mill_critical_speeds(
                mill, plan.critical_speed, control.nested(control.thread_budget())));
        } else {
            tandem_sweep_detail::StabilityPoint at{core::mill_stability_at(mill), {}};
            at.root = core::describe_rightmost_root(mill, at.at);
            point = tandem_sweep_detail::stability_point_table().write(at);
        }
        point[key] = plan.values[i];
        points.push_back(std::move(point));
        control.report(static_cast<double>(i + 1 - first) / static_cast<double>(count));
    }
    return points;
}

nlohmann::json tandem_sweep_result_json(const TandemSweepPlan& plan, nlohmann::json points) {
    return tandem_sweep_detail::result_table().write({&plan, std::move(points)});
}

std::vector<ResultSchema> tandem_sweep_result_schemas() {
    return {{tandem_sweep_detail::critical_point_table().component(),
             sweep_point_schema(tandem_sweep_detail::critical_point_table().schema())},
            {tandem_sweep_detail::stability_point_table().component(),
             sweep_point_schema(tandem_sweep_detail::stability_point_table().schema())},
            result_schema(tandem_sweep_detail::result_table())};
}

std::span<const CsvTable> tandem_sweep_csv_tables() {
    static const std::vector<CsvTable> tables{
        {"points",
         "One row per swept value, the value first.",
         "",
         {},
         "/points",
         [](const nlohmann::json& result) {
             std::vector<std::string> columns{result.value("value_name", std::string("value"))};
             const bool stability = result.value("quantity", std::string()) == "stability";
             for (std::string& name : stability
                                          ? tandem_sweep_detail::stability_point_table().names()
                                          : tandem_sweep_detail::critical_point_table().names())
                 columns.push_back(std::move(name));
             return columns;
         }}};
    return tables;
}

}  // namespace rollgap::api
