#include "api/tandem_points.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <string_view>

#include "api/chatter_json.h"
#include "api/json_pointer.h"
#include "api/quantity_json.h"
#include "api/result_table.h"
#include "api/scenario_schema.h"
#include "api/stability_json.h"
#include "api/tandem_json.h"
#include "api/tandem_result_json.h"
#include "api/tandem_schema.h"
#include "api/text.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_stability.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside the stand's sweep and the tandem
// answer, whose anonymous helpers have the same names.
namespace tandem_points_detail {

using nlohmann::json;
using namespace units;

constexpr std::string_view parameter_name = "parameter";
constexpr std::string_view quantity_name = "quantity";
constexpr std::string_view critical_speed_member = "critical_speed";
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

// Each point written into the resolved document and read back as a request's tandem is.
TandemValues build_values(const std::vector<SweepPoint>& points, const json& base,
                          const std::string& parameter, FieldErrors& errors) {
    TandemValues built;
    const std::string field_pointer = concat("/tandem", parameter);
    bool interior_reported = false;
    for (const SweepPoint& point : points) {
        if (!point.value.is_number()) {
            errors.add({point.pointer,
                        concat("must be a number, got ", json_type_name(point.value)), std::nullopt,
                        std::nullopt});
            continue;
        }
        FieldErrors point_errors;
        core::Mill swept = mill_from_json(
            with_tandem_value(base, parameter, point.value.get<double>()), "/tandem", point_errors);
        if (point_errors.empty()) {
            built.values.push_back(point.value.get<double>());
            built.mills.push_back(std::move(swept));
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
                            concat(where, "with ", parameter, " = ",
                                   format_number(point.value.get<double>()),
                                   " the mill is invalid at ", error.pointer, ": ", error.detail),
                            std::nullopt, std::nullopt});
            }
        }
    }
    return built;
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
            {"chatter_type",
             "The headline crossing's chatter type by shape: the moving stand's six masses in its "
             "motion, classified as a single stand's mode (docs/model.md, \"Chatter type\").",
             chatter_type_schema(true),
             [](const S& s) {
                 const core::MillCrossing* h = headline_of(s);
                 return h != nullptr ? json(core::to_string(h->chatter.type)) : json(nullptr);
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
            {"chatter_type",
             "The rightmost root's chatter type by shape (the moving stand's six masses in its "
             "motion, docs/model.md, \"Chatter type\").",
             chatter_type_schema(true),
             [](const P& p) {
                 return p.root.found ? json(core::to_string(p.root.described.chatter.type))
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

}  // namespace tandem_points_detail

std::vector<std::string> with_tandem_point_columns(std::vector<std::string> lead,
                                                   const nlohmann::json& result) {
    const bool stability = result.value("quantity", std::string()) == "stability";
    for (std::string& name : tandem_point_columns(stability ? TandemSweepQuantity::stability
                                                            : TandemSweepQuantity::critical_speed))
        lead.push_back(std::move(name));
    return lead;
}

std::string_view to_string(TandemSweepQuantity quantity) {
    return quantity == TandemSweepQuantity::stability ? "stability" : "critical_speed";
}

void read_tandem_point_spec(const OptionsReader& reader, TandemPointSpec& spec,
                            nlohmann::json& echo) {
    using tandem_points_detail::critical_speed_member;
    using tandem_points_detail::quantity_name;
    std::string quantity = "critical_speed";
    bool quantity_valid = true;
    if (const nlohmann::json* value = reader.find(quantity_name)) {
        if (auto choice = read_choice(*value, reader.at(quantity_name),
                                      tandem_points_detail::quantities, reader.errors())) {
            quantity = std::move(*choice);
        } else {
            quantity_valid = false;
        }
    }
    spec.quantity = quantity == "stability" ? TandemSweepQuantity::stability
                                            : TandemSweepQuantity::critical_speed;
    echo[std::string(quantity_name)] = quantity;
    if (quantity_valid && spec.quantity == TandemSweepQuantity::critical_speed) {
        spec.critical_speed =
            critical_speed_options_from_json(reader.object_or_defaults(critical_speed_member),
                                             reader.at(critical_speed_member), reader.errors());
        echo[std::string(critical_speed_member)] = critical_speed_options_json(spec.critical_speed);
    } else if (quantity_valid && reader.given(critical_speed_member)) {
        reader.errors().add({reader.at(critical_speed_member),
                             "applies to quantity 'critical_speed' only; this one's quantity is "
                             "'stability'",
                             std::nullopt, std::nullopt});
    }
}

std::optional<std::string> read_tandem_parameter(const OptionsReader& reader,
                                                 const nlohmann::json* document, Unit& unit) {
    return tandem_points_detail::read_parameter(reader, document, unit);
}

bool tandem_parameters_overlap(const std::string& a, const std::string& b) {
    const std::string& shorter = a.size() <= b.size() ? a : b;
    const std::string& longer = a.size() <= b.size() ? b : a;
    return longer == shorter || longer.starts_with(shorter + "/");
}

nlohmann::json with_tandem_value(nlohmann::json document, const std::string& parameter,
                                 double value) {
    nlohmann::json& target = document[nlohmann::json::json_pointer(parameter)];
    if (target.is_array()) {
        for (nlohmann::json& element : target) element = value;  // a list set whole
    } else {
        target = value;
    }
    return document;
}

TandemValues tandem_values(const std::vector<SweepPoint>& points, const nlohmann::json& base,
                           const std::string& parameter, FieldErrors& errors) {
    return tandem_points_detail::build_values(points, base, parameter, errors);
}

nlohmann::json tandem_point_json(const core::Mill& mill, const TandemPointSpec& spec,
                                 const core::Control& control) {
    if (spec.quantity == TandemSweepQuantity::critical_speed) {
        // The point's own search reports no progress: the points do.
        return tandem_points_detail::critical_point_table().write(core::mill_critical_speeds(
            mill, spec.critical_speed, control.nested(control.thread_budget())));
    }
    tandem_points_detail::StabilityPoint at{core::mill_stability_at(mill), {}};
    at.root = core::describe_rightmost_root(mill, at.at);
    return tandem_points_detail::stability_point_table().write(at);
}

std::string_view tandem_point_component(TandemSweepQuantity quantity) {
    return quantity == TandemSweepQuantity::stability
               ? tandem_points_detail::stability_point_table().component()
               : tandem_points_detail::critical_point_table().component();
}

nlohmann::json tandem_point_schema(TandemSweepQuantity quantity) {
    return quantity == TandemSweepQuantity::stability
               ? tandem_points_detail::stability_point_table().schema()
               : tandem_points_detail::critical_point_table().schema();
}

std::vector<std::string> tandem_point_columns(TandemSweepQuantity quantity) {
    return quantity == TandemSweepQuantity::stability
               ? tandem_points_detail::stability_point_table().names()
               : tandem_points_detail::critical_point_table().names();
}

}  // namespace rollgap::api
