// Reading the stability analysis' options and the critical-speed search's (api/stability_json.h),
// and their echo; the result writer is in stability_json.cpp.
#include "api/stability_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <string_view>
#include <vector>

#include "api/chatter_json.h"
#include "api/option_table.h"
#include "api/options_reader.h"
#include "api/result_table.h"
#include "api/quantity_json.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view detail_name = "detail";
constexpr std::array<std::string_view, 2> detail_choices{"full", "summary"};

constexpr std::string_view speed_min_name = option_name(OptionId::search_speed_min);
constexpr std::string_view speed_max_name = option_name(OptionId::search_speed_max);
constexpr std::string_view speed_step_name = option_name(OptionId::search_speed_step);

constexpr std::array<std::string_view, 4> search_members{
    speed_min_name, speed_max_name, speed_step_name, option_name(OptionId::search_tolerance)};
constexpr std::array<std::string_view, 6> stability_members{speed_min_name,
                                                            speed_max_name,
                                                            speed_step_name,
                                                            option_name(OptionId::search_tolerance),
                                                            option_name(OptionId::critical_speed),
                                                            detail_name};

// The speeds a search may scan (the search's own bounds).
Interval speed_range() { return option(OptionId::search_speed_min).range; }

void read_search(const OptionsReader& reader, core::CriticalSpeedOptions& search) {
    reader.read(OptionId::search_speed_min, search.speed_min);
    reader.read(OptionId::search_speed_max, search.speed_max);
    reader.read(OptionId::search_speed_step, search.speed_step);
    reader.read(OptionId::search_tolerance, search.relative_tolerance);

    // Cross-member rules, each only on members that passed their own checks.
    if (reader.failed(speed_min_name) || reader.failed(speed_max_name)) return;
    if (search.speed_min >= search.speed_max) {
        const Interval allowed = open_closed(search.speed_min, speed_range().max);
        reader.errors().add(
            {reader.at(speed_max_name),
             concat("the search range must not be empty: speed_max_m_per_s ",
                    format_number(search.speed_max), " m/s must be above speed_min_m_per_s ",
                    format_number(search.speed_min), " m/s"),
             allowed.text(), std::string(units::metre_per_second.code)});
        return;
    }
    if (reader.failed(speed_step_name)) return;
    if (scan_point_count(search) > max_scan_points) {
        // The smallest step that keeps the scan within the limit, rounded up to 3 digits.
        const double smallest = (search.speed_max - search.speed_min) / (max_scan_points - 1);
        const int exponent = static_cast<int>(std::floor(std::log10(smallest))) - 2;
        const double digits = std::ceil(smallest / std::pow(10.0, exponent));
        const double rounded =
            to_si(digits, Unit{"", exponent});  // digits × 10^exponent, exactly rounded
        const Interval allowed = closed(rounded, option(OptionId::search_speed_step).range.max);
        reader.errors().add(
            {reader.at(speed_step_name),
             concat("a step of ", format_number(search.speed_step), " m/s scans ",
                    std::to_string(scan_point_count(search)), " speeds between ",
                    format_number(search.speed_min), " and ", format_number(search.speed_max),
                    " m/s; at most ", std::to_string(max_scan_points),
                    " are allowed: use a larger step or a narrower range (the critical speed "
                    "is refined to relative_tolerance whatever the step)"),
             allowed.text(), std::string(units::metre_per_second.code)});
    }
}

nlohmann::json search_json(const core::CriticalSpeedOptions& search) {
    nlohmann::json document = nlohmann::json::object();
    put_option(document, OptionId::search_speed_min, search.speed_min);
    put_option(document, OptionId::search_speed_max, search.speed_max);
    put_option(document, OptionId::search_speed_step, search.speed_step);
    put_option(document, OptionId::search_tolerance, search.relative_tolerance);
    return document;
}

}  // namespace

void read_critical_speed_search(const OptionsReader& reader, core::CriticalSpeedOptions& search) {
    read_search(reader, search);
}

std::span<const std::string_view> critical_speed_search_members() { return search_members; }

void read_detail(const OptionsReader& reader, Detail& detail) {
    const nlohmann::json* value = reader.find(detail_name);
    if (value == nullptr) return;
    if (const auto choice =
            read_choice(*value, reader.at(detail_name), detail_choices, reader.errors())) {
        detail = *choice == "summary" ? Detail::summary : Detail::full;
    }
}

nlohmann::json detail_json(Detail detail) { return detail == Detail::summary ? "summary" : "full"; }

int scan_point_count(const core::CriticalSpeedOptions& options) {
    // As core::critical_speed counts them.
    const double step = std::min(options.speed_step, 0.5);
    const double intervals = std::ceil((options.speed_max - options.speed_min) / step - 1e-9);
    if (!(intervals < 1e9)) return std::numeric_limits<int>::max();
    return std::max(2, static_cast<int>(intervals) + 1);
}

StabilityOptions read_stability_options(const OptionsReader& reader) {
    StabilityOptions parsed;
    read_search(reader, parsed.search);
    reader.read(OptionId::critical_speed, parsed.critical_speed);
    read_detail(reader, parsed.detail);
    return parsed;
}

std::span<const std::string_view> stability_option_members() { return stability_members; }

StabilityOptions stability_options_from_json(const nlohmann::json& options,
                                             const std::string& pointer, FieldErrors& errors) {
    const OptionsReader reader(options, pointer, stability_members, errors);
    return read_stability_options(reader);
}

nlohmann::json stability_options_json(const StabilityOptions& options) {
    nlohmann::json document = search_json(options.search);
    put_option(document, OptionId::critical_speed, options.critical_speed);
    document[detail_name] = detail_json(options.detail);
    return document;
}

core::CriticalSpeedOptions critical_speed_options_from_json(const nlohmann::json& options,
                                                            const std::string& pointer,
                                                            FieldErrors& errors) {
    core::CriticalSpeedOptions parsed;
    const OptionsReader reader(options, pointer, search_members, errors);
    read_search(reader, parsed);
    return parsed;
}

nlohmann::json critical_speed_options_json(const core::CriticalSpeedOptions& options) {
    return search_json(options);
}

}  // namespace rollgap::api
