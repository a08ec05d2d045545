// Reading the mill speed limit's options (the plant's limits, mill-wide and per stand) and
// writing its result (api/tandem_speed_limit_json.h; docs/model.md §13.5).
#include "api/tandem_speed_limit_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/speed_limit_json.h"
#include "api/stability_json.h"
#include "api/tandem_result_json.h"
#include "api/tandem_uncertainty_json.h"
#include "api/text.h"

namespace rollgap::api {
// Named, not anonymous: the unity build puts this file beside tandem_result_json.cpp.
namespace tandem_speed_limit_detail {

using nlohmann::json;
using std::string_view_literals::operator""sv;

constexpr std::string_view stands_name = "stands";
constexpr std::string_view changes_name = "changes";
constexpr std::string_view posteriors_name = "posteriors";
constexpr std::array<OptionId, 4> limit_ids{OptionId::max_roll_force, OptionId::max_torque,
                                            OptionId::max_power, OptionId::min_forward_slip};

const std::vector<std::string_view>& option_members() {
    static const std::vector<std::string_view> members = [] {
        std::vector<std::string_view> out(critical_speed_search_members().begin(),
                                          critical_speed_search_members().end());
        for (const OptionId id : limit_ids) out.push_back(option_name(id));
        out.push_back(option_name(OptionId::chatter_limit));
        out.push_back(option_name(OptionId::chatter_margin));
        out.push_back(option_name(OptionId::confidence));
        out.push_back(option_name(OptionId::samples));
        out.push_back(option_name(OptionId::seed));
        out.push_back(option_name(OptionId::what_to_change));
        out.push_back(stands_name);
        out.push_back(changes_name);
        out.push_back(posteriors_name);
        return out;
    }();
    return members;
}

const std::vector<std::string_view>& stand_members() {
    static const std::vector<std::string_view> members = [] {
        std::vector<std::string_view> out;
        for (const OptionId id : limit_ids) out.push_back(option_name(id));
        return out;
    }();
    return members;
}

// The member of PlantLimits an option row sets (const or not).
template <class Limits>
auto& limit_of(Limits& limits, OptionId id) {
    switch (id) {
        case OptionId::max_roll_force: return limits.max_force;
        case OptionId::max_torque: return limits.max_torque;
        case OptionId::max_power: return limits.max_power;
        default: return limits.min_forward_slip;
    }
}

// The four limits of one options object (the mill-wide ones or a stand's) onto `limits`.
void read_limits(const OptionsReader& reader, core::PlantLimits& limits) {
    for (const OptionId id : limit_ids) {
        double value = 0.0;
        if (reader.read(id, value)) limit_of(limits, id) = value;
    }
}

json limits_json(const core::PlantLimits& limits) {
    json document = json::object();
    for (const OptionId id : limit_ids)
        if (const std::optional<double>& value = limit_of(limits, id))
            put_option(document, id, *value);
    return document;
}

// --- the result ---------------------------------------------------------------------------

json kind_or_null(const std::optional<core::SpeedLimitKind>& kind) {
    return speed_limit_kind_json(kind);
}

json kind_schema(bool nullable) { return speed_limit_kind_schema(nullable); }

const ResultTable<core::LimitAnswer>& check_table() {
    static const ResultTable<core::LimitAnswer> table = [] {
        std::vector<Member<core::LimitAnswer>> members{
            {"stand",
             "The stand the limit belongs to, from 1 at the entry; for chatter the stand that "
             "moves in the headline crossing; null for the mill's steady state (and for chatter "
             "without a crossing).",
             stand_number_schema(true),
             [](const core::LimitAnswer& a) { return stand_number(a.stand); }},
        };
        for (Member<core::LimitAnswer>& member : speed_limit_check_members())
            members.push_back(std::move(member));
        return ResultTable<core::LimitAnswer>{
            "TandemSpeedLimitCheck",
            "One checked limit of one stand (or of the mill): the plant's value, the figure at "
            "the mill speed and the mill speeds where the limit binds, in `unit`.",
            std::move(members)};
    }();
    return table;
}

// How the chatter limit was set: by the headline crossing, by none in the range, or by none
// inside the model's range although crossings outside it were found (docs/model.md §12.7).
std::string chatter_basis(const TandemSpeedLimitReport& r) {
    if (!r.result.critical) return "not_checked";
    const core::MillCriticalSpeeds& c = *r.result.critical;
    if (c.headline >= 0) return "headline";
    for (const core::LimitAnswer& a : r.result.window.limits)
        if (a.kind == core::SpeedLimitKind::chatter && a.limit < 0.0)
            return "unstable_at_lowest_speed";
    return c.outside_range_below.empty() ? "none_in_range" : "outside_model_range";
}

std::string stand_text(int index) { return concat("stand ", std::to_string(index + 1)); }

const ResultTable<TandemSpeedLimitReport>& result_table() {
    using R = TandemSpeedLimitReport;
    static const ResultTable<R> table{
        "TandemSpeedLimitResult",
        "The mill speeds the tandem mill may run at under the plant's limits (docs/model.md "
        "§13.5): the permitted window around the mill speed, the limit and stand binding at "
        "each end, every checked limit and the advised mill speed.",
        {
            {"status",
             "ok: a permitted window (the mill speed inside it or not); no_window: no mill speed "
             "in the range meets every checked limit.",
             enum_schema({"ok", "no_window", "no_operating"}),
             [](const R& r) { return json(core::to_string(r.result.window.status)); }},
            {"summary", "The answer in one sentence, for people.", string_schema(),
             [](const R& r) { return json(tandem_speed_limit_summary(r)); }},
            {"operating_speed_m_per_s", "The mill speed: the last stand's roll speed.",
             number_schema(units::metre_per_second, false),
             [](const R& r) { return json(r.result.window.operating_speed); }},
            {"advised_speed_m_per_s",
             "The highest permitted mill speed: the window's upper end, the chatter limit taken "
             "at V_c (1 - margin); null without a window.",
             number_schema(units::metre_per_second),
             [](const R& r) {
                 return r.result.window.status == core::SpeedLimitStatus::ok
                            ? json(r.result.window.advised_speed)
                            : json(nullptr);
             }},
            {"binding_limit",
             "The limit that sets the advised speed; null when it is the range's highest speed.",
             kind_schema(true),
             [](const R& r) { return kind_or_null(r.result.window.binding_max); }},
            {"binding_stand",
             "The stand whose limit sets the advised speed (for chatter the stand that moves); "
             "null with no binding limit or a limit of the whole mill.",
             stand_number_schema(true),
             [](const R& r) {
                 return r.result.window.binding_max
                            ? stand_number(r.result.window.binding_max_stand)
                            : json(nullptr);
             }},
            {"window_min_m_per_s", "The permitted window's lower end; null without a window.",
             number_schema(units::metre_per_second),
             [](const R& r) {
                 return r.result.window.status == core::SpeedLimitStatus::ok
                            ? json(r.result.window.window_min)
                            : json(nullptr);
             }},
            {"window_max_m_per_s", "The permitted window's upper end (the advised speed).",
             number_schema(units::metre_per_second),
             [](const R& r) {
                 return r.result.window.status == core::SpeedLimitStatus::ok
                            ? json(r.result.window.window_max)
                            : json(nullptr);
             }},
            {"binding_min",
             "The limit that sets the window's lower end (a force limit usually does); null when "
             "it is the range's lowest speed.",
             kind_schema(true),
             [](const R& r) { return kind_or_null(r.result.window.binding_min); }},
            {"binding_min_stand", "The stand of binding_min; null as binding_stand is.",
             stand_number_schema(true),
             [](const R& r) {
                 return r.result.window.binding_min
                            ? stand_number(r.result.window.binding_min_stand)
                            : json(nullptr);
             }},
            {"operating_permitted", "Whether the mill speed lies in the window.", boolean_schema(),
             [](const R& r) { return json(r.result.window.operating_permitted); }},
            {"checked",
             "The kinds of limit checked: steady_state always, the others when the options give "
             "them for at least one stand (chatter unless chatter is false).",
             array_schema(kind_schema(false)),
             [](const R& r) {
                 json names = json::array();
                 for (const core::LimitAnswer& a : r.result.window.limits)
                     if (std::find(names.begin(), names.end(), core::to_string(a.kind)) ==
                         names.end())
                         names.push_back(core::to_string(a.kind));
                 return names;
             }},
            {"chatter_basis",
             "What set the chatter limit: headline (the mill's headline critical speed); "
             "none_in_range (no crossing in the range: the range's highest speed); "
             "outside_model_range (crossings were found only outside the model's range of "
             "validity, critical_speeds.outside_range_below: the range's highest speed, and the "
             "model cannot vouch for the speeds above them); unstable_at_lowest_speed (no speed "
             "is permitted); not_checked.",
             enum_schema({"headline", "none_in_range", "outside_model_range",
                          "unstable_at_lowest_speed", "not_checked"}),
             [](const R& r) { return json(chatter_basis(r)); }},
            {"limits",
             "Every checked limit: the mill's steady state, then each stand's limits from the "
             "entry (force, torque, power, skid), then chatter.",
             array_schema(ref_schema("TandemSpeedLimitCheck")),
             [](const R& r) {
                 json rows = json::array();
                 for (const core::LimitAnswer& a : r.result.window.limits)
                     rows.push_back(check_table().write(a));
                 return rows;
             }},
            {"uncertainty",
             "The headline critical speed's uncertainty from options.posteriors; null without "
             "them or without a headline crossing.",
             ref_schema("TandemCriticalSpeedUncertainty", true),
             [](const R& r) {
                 if (!r.result.uncertainty || !r.result.critical) return json(nullptr);
                 return mill_uncertainty_json(*r.result.critical, *r.result.uncertainty,
                                              r.limits.confidence, r.posteriors);
             }},
            {"what_to_change",
             "What to change to run the mill faster (null when options.what_to_change is "
             "false).",
             ref_schema("TandemWhatToChange", true),
             [](const R& r) {
                 return r.what_to_change ? mill_what_to_change_json(*r.what_to_change)
                                         : json(nullptr);
             }},
            {"critical_speeds",
             "The mill's critical speeds behind the chatter limit (null when chatter is not "
             "checked).",
             ref_schema("TandemCriticalSpeeds", true),
             [](const R& r) {
                 return r.result.critical ? tandem_critical_speeds_json(*r.result.critical)
                                          : json(nullptr);
             }},
        }};
    return table;
}

const std::array<CsvTable, 1> csv_tables{{
    {"limits",
     "One row per checked limit, led by its stand.",
     "",
     {},
     "/limits",
     [](const json&) { return check_table().names(); }},
}};

}  // namespace tandem_speed_limit_detail

namespace detail = tandem_speed_limit_detail;

TandemSpeedLimitOptions tandem_speed_limit_options_from_json(const nlohmann::json& options,
                                                             const std::string& pointer,
                                                             const core::Mill* valid_mill,
                                                             FieldErrors& errors) {
    const int stands = valid_mill != nullptr ? valid_mill->size() : 0;
    TandemSpeedLimitOptions out;
    const OptionsReader reader(options, pointer, detail::option_members(), errors);
    read_critical_speed_search(reader, out.search);
    detail::read_limits(reader, out.mill_wide);
    reader.read(OptionId::chatter_limit, out.limits.chatter);
    reader.read(OptionId::chatter_margin, out.limits.chatter_margin);
    out.limits.stands.assign(static_cast<std::size_t>(std::max(stands, 0)), out.mill_wide);
    reader.read(OptionId::confidence, out.limits.confidence);
    const nlohmann::json* posteriors = reader.find(detail::posteriors_name);
    if (posteriors != nullptr && !posteriors->is_null()) {
        if (std::optional<MillPosteriors> read = read_mill_posteriors(
                *posteriors, reader.at(detail::posteriors_name), valid_mill, errors)) {
            out.posteriors = std::move(read->stands);
            out.limits.posterior = std::move(read->mill);
        }
    }
    int seed = 1;
    reader.read(OptionId::samples, out.limits.samples);
    if (reader.read(OptionId::seed, seed)) out.limits.seed = static_cast<std::uint64_t>(seed);
    const std::string samples_at = reader.at(option_name(OptionId::samples));
    if (out.limits.samples > 0 && (posteriors == nullptr || posteriors->is_null())) {
        errors.add({samples_at,
                    "draws need posteriors to draw from: give options.posteriors (each stand's "
                    "calibration posterior, or null) or set samples to 0",
                    std::nullopt, std::nullopt});
    }
    if (out.limits.samples > 0 && !out.limits.chatter &&
        !errors.has_error_at_or_below(samples_at)) {
        errors.add({samples_at,
                    "the draws check the critical speed's uncertainty, which is not used when "
                    "chatter is false: set samples to 0",
                    std::nullopt, std::nullopt});
    }
    reader.read(OptionId::what_to_change, out.what_to_change);
    if (const nlohmann::json* changes = reader.find(detail::changes_name))
        read_mill_changes(*changes, reader.at(detail::changes_name), stands, out.changes, errors);
    else out.changes = default_mill_change_fields(stands);
    const nlohmann::json* list = reader.find(detail::stands_name);
    if (list == nullptr || list->is_null()) return out;
    const std::string at = reader.at(detail::stands_name);
    if (!check_per_stand_list(*list, at, stands, "object",
                              ", each with the limits that differ from the mill-wide ones, e.g. "
                              "[{}, {\"max_roll_force_kN\": 12000}]",
                              errors))
        return out;
    // each stand's limits read even when the count is wrong (every violation at once), at most
    // a mill's most stands
    const std::size_t read = std::min(list->size(), std::size_t{core::max_mill_stands});
    for (std::size_t i = 0; i < read; ++i) {
        const OptionsReader stand(list->at(i), concat(at, "/", std::to_string(i)),
                                  detail::stand_members(), errors);
        if (i < out.limits.stands.size()) detail::read_limits(stand, out.limits.stands[i]);
    }
    return out;
}

nlohmann::json tandem_speed_limit_options_json(const TandemSpeedLimitOptions& options) {
    nlohmann::json document = critical_speed_options_json(options.search);
    for (const OptionId id : detail::limit_ids)
        if (const std::optional<double>& value = detail::limit_of(options.mill_wide, id))
            put_option(document, id, *value);
    put_option(document, OptionId::chatter_limit, options.limits.chatter);
    put_option(document, OptionId::chatter_margin, options.limits.chatter_margin);
    nlohmann::json stands = nlohmann::json::array();
    for (const core::PlantLimits& stand : options.limits.stands)
        stands.push_back(detail::limits_json(stand));
    document[std::string(detail::stands_name)] = std::move(stands);
    put_option(document, OptionId::confidence, options.limits.confidence);
    put_option(document, OptionId::samples, options.limits.samples);
    put_option(document, OptionId::seed, static_cast<int>(options.limits.seed));
    put_option(document, OptionId::what_to_change, options.what_to_change);
    document[std::string(detail::changes_name)] = mill_changes_json(options.changes);
    nlohmann::json posteriors(nullptr);
    if (!options.posteriors.empty()) {
        posteriors = nlohmann::json::array();
        for (const std::optional<Posterior>& p : options.posteriors)
            posteriors.push_back(p ? posterior_json(*p) : nlohmann::json(nullptr));
    }
    document[std::string(detail::posteriors_name)] = std::move(posteriors);
    return document;
}

std::string tandem_speed_limit_summary(const TandemSpeedLimitReport& report) {
    const core::SpeedLimitResult& r = report.result.window;
    const std::string at = concat("The mill runs at ", summary_speed_text(r.operating_speed));
    if (r.status != core::SpeedLimitStatus::ok)
        return concat(at, "; no mill speed in the range meets every checked limit (see limits).");
    std::string binding = "range's highest speed";
    if (r.binding_max) {
        binding = concat(core::to_string(*r.binding_max), " limit");
        if (r.binding_max_stand >= 0)
            binding += concat(" of ", detail::stand_text(r.binding_max_stand));
    }
    for (const core::LimitAnswer& a : r.limits) {
        if (r.binding_max && *r.binding_max == core::SpeedLimitKind::chatter &&
            a.kind == core::SpeedLimitKind::chatter && std::isfinite(a.utilisation)) {
            const std::string moving =
                a.stand >= 0 ? concat(" (", detail::stand_text(a.stand), " moves)") : std::string();
            return concat(at, ", ", summary_percent_text(a.utilisation), " of its ",
                          summary_speed_text(a.limit), " chatter limit", moving, "; it may run at ",
                          summary_speed_text(r.window_min), " to ",
                          summary_speed_text(r.window_max), ".");
        }
    }
    return concat(at, (r.operating_permitted ? " (permitted)" : " (not permitted)"),
                  "; it may run at ", summary_speed_text(r.window_min), " to ",
                  summary_speed_text(r.window_max), ", the upper end set by the ", binding, ".");
}

nlohmann::json tandem_speed_limit_result_json(const TandemSpeedLimitReport& report) {
    return detail::result_table().write(report);
}

std::vector<ResultSchema> tandem_speed_limit_result_schemas() {
    std::vector<ResultSchema> out{result_schema(detail::check_table()),
                                  result_schema(detail::result_table())};
    for (ResultSchema& schema : mill_uncertainty_schemas()) out.push_back(std::move(schema));
    for (ResultSchema& schema : mill_what_to_change_schemas()) out.push_back(std::move(schema));
    return out;
}

std::span<const CsvTable> tandem_speed_limit_csv_tables() { return detail::csv_tables; }

}  // namespace rollgap::api
