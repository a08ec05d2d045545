#include "api/stability_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <string_view>
#include <vector>

#include "api/options_reader.h"
#include "api/quantity_json.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

constexpr std::string_view speed_min_name = "speed_min_m_per_s";
constexpr std::string_view speed_max_name = "speed_max_m_per_s";
constexpr std::string_view speed_step_name = "speed_step_m_per_s";
constexpr std::string_view tolerance_name = "relative_tolerance";
constexpr std::string_view critical_speed_name = "critical_speed";

constexpr std::array<std::string_view, 4> search_members{speed_min_name, speed_max_name, speed_step_name,
                                                         tolerance_name};
constexpr std::array<std::string_view, 5> stability_members{speed_min_name, speed_max_name, speed_step_name,
                                                            tolerance_name, critical_speed_name};

// The speeds a search may scan are the speeds a scenario may have.
Interval speed_range() { return find_scenario_field("/rolls/speed_m_per_s")->range; }

void read_search(const OptionsReader& reader, core::CriticalSpeedOptions& search) {
    reader.number(speed_min_name, units::metre_per_second, speed_range(), search.speed_min);
    reader.number(speed_max_name, units::metre_per_second, speed_range(), search.speed_max);
    reader.number(speed_step_name, units::metre_per_second, open_closed(0.0, 0.5), search.speed_step);
    reader.number(tolerance_name, units::one, closed(1e-8, 1e-2), search.relative_tolerance);

    // Cross-member rules, each only on members that passed their own checks.
    if (reader.failed(speed_min_name) || reader.failed(speed_max_name)) return;
    if (search.speed_min >= search.speed_max) {
        const Interval allowed = open_closed(search.speed_min, speed_range().max);
        reader.errors().add({reader.at(speed_max_name),
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
        const double rounded = to_si(digits, Unit{"", exponent});  // digits × 10^exponent, exactly rounded
        const Interval allowed = closed(rounded, 0.5);
        reader.errors().add({reader.at(speed_step_name),
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
    return {
        {speed_min_name, echo(search.speed_min, units::metre_per_second)},
        {speed_max_name, echo(search.speed_max, units::metre_per_second)},
        {speed_step_name, echo(search.speed_step, units::metre_per_second)},
        {tolerance_name, search.relative_tolerance},
    };
}

nlohmann::json shape_json(const core::Vector6& shape) {
    nlohmann::json values = nlohmann::json::array();
    for (int i = 0; i < 6; ++i) values.push_back(quantity_json(shape(i), units::one));
    return values;
}

// Largest |component| 1, its sign positive; a zero vector (no shape known) stays zero.
core::Vector6 normalised(const core::Vector6& shape) {
    core::Vector6::Index largest = 0;
    const double magnitude = shape.cwiseAbs().maxCoeff(&largest);
    if (!(magnitude > 0.0)) return shape;
    return shape / (shape(largest) < 0.0 ? -magnitude : magnitude);
}

bool linearised(const core::SpeedStability& stability) {
    return stability.steady_status == core::BiteStatus::ok && stability.status == core::DynamicsStatus::ok;
}

std::string stability_status(const core::SpeedStability& stability) {
    if (stability.steady_status != core::BiteStatus::ok) return "no_steady_state";
    return core::to_string(stability.status);
}

// A mode of the coupled model (its shape has phases): with its chatter type (docs/model.md,
// "Chatter type") and the type its frequency band alone suggests.
nlohmann::json classified_mode_json(const core::Eigenmode& mode) {
    nlohmann::json body = eigenmode_json(mode);
    body["chatter_type"] = core::to_string(mode.chatter.type);
    body["chatter_band"] = core::to_string(mode.chatter.band);
    return body;
}

nlohmann::json nullable_mode(bool known, const core::Eigenmode& mode) {
    return known ? classified_mode_json(mode) : nlohmann::json(nullptr);
}

}  // namespace

int scan_point_count(const core::CriticalSpeedOptions& options) {
    // As core::critical_speed counts them.
    const double step = std::min(options.speed_step, 0.5);
    const double intervals = std::ceil((options.speed_max - options.speed_min) / step - 1e-9);
    if (!(intervals < 1e9)) return std::numeric_limits<int>::max();
    return std::max(2, static_cast<int>(intervals) + 1);
}

StabilityOptions stability_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                             FieldErrors& errors) {
    StabilityOptions parsed;
    const OptionsReader reader(options, pointer, stability_members, errors);
    read_search(reader, parsed.search);
    reader.boolean(critical_speed_name, parsed.critical_speed);
    return parsed;
}

nlohmann::json stability_options_json(const StabilityOptions& options) {
    nlohmann::json document = search_json(options.search);
    document[critical_speed_name] = options.critical_speed;
    return document;
}

core::CriticalSpeedOptions critical_speed_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                                            FieldErrors& errors) {
    core::CriticalSpeedOptions parsed;
    const OptionsReader reader(options, pointer, search_members, errors);
    read_search(reader, parsed);
    return parsed;
}

nlohmann::json critical_speed_options_json(const core::CriticalSpeedOptions& options) { return search_json(options); }

nlohmann::json eigenmode_json(const core::Eigenmode& mode) {
    return {
        {"frequency_Hz", quantity_json(mode.frequency_Hz, units::hertz)},
        {"damping_ratio", quantity_json(mode.damping_ratio, units::one)},
        {"growth_rate_per_s", quantity_json(mode.eigenvalue.real(), units::per_second)},
        {"shape", shape_json(mode.shape)},
    };
}

nlohmann::json speed_stability_summary_json(const core::SpeedStability& stability) {
    const bool known = linearised(stability);
    return {
        {"status", stability_status(stability)},
        {"steady_status", core::to_string(stability.steady_status)},
        {"stable", known ? nlohmann::json(stability.stable) : nlohmann::json(nullptr)},
        {"max_growth_rate_per_s", known ? quantity_json(stability.max_real_part, units::per_second) : nullptr},
        // k4 is known once the steady bite is, even if the linearisation then failed.
        {"strip_stiffness_GN_per_m", stability.steady_status == core::BiteStatus::ok && stability.strip_stiffness > 0.0
                                         ? quantity_json(stability.strip_stiffness, units::giganewton_per_metre)
                                         : nullptr},
        {"least_damped_mode", nullable_mode(known && !stability.oscillatory.empty(), stability.least_damped)},
    };
}

nlohmann::json speed_stability_json(const core::SpeedStability& stability) {
    const bool known = linearised(stability);
    nlohmann::json body = speed_stability_summary_json(stability);
    body["speed_m_per_s"] = quantity_json(stability.speed, units::metre_per_second);
    body["force_kN"] = stability.steady_status == core::BiteStatus::ok
                           ? quantity_json(stability.force, units::kilonewton)
                           : nullptr;
    nlohmann::json modes = nlohmann::json::array();
    for (const core::Eigenmode& mode : stability.oscillatory) modes.push_back(classified_mode_json(mode));
    body["oscillatory_modes"] = std::move(modes);

    // Least damped first; conjugates by ascending imaginary part. Deterministic whatever order
    // the eigensolver returns them in.
    std::vector<std::complex<double>> eigenvalues = stability.eigenvalues;
    std::sort(eigenvalues.begin(), eigenvalues.end(), [](const auto& a, const auto& b) {
        return a.real() != b.real() ? a.real() > b.real() : a.imag() < b.imag();
    });
    nlohmann::json values = nlohmann::json::array();
    if (known) {
        for (const auto& lambda : eigenvalues) {
            values.push_back({{"real_per_s", quantity_json(lambda.real(), units::per_second)},
                              {"imag_per_s", quantity_json(lambda.imag(), units::per_second)}});
        }
    }
    body["eigenvalues"] = std::move(values);
    return body;
}

nlohmann::json structure_modes_json(const core::ModalAnalysis& modal, double strip_stiffness) {
    nlohmann::json frequencies = nlohmann::json::array(), shapes = nlohmann::json::array();
    for (const core::NaturalMode& mode : modal.natural) {
        frequencies.push_back(quantity_json(mode.frequency_Hz, units::hertz));
        shapes.push_back(shape_json(normalised(mode.shape)));
    }
    nlohmann::json damped = nlohmann::json::array();
    for (const core::DampedMode& mode : modal.damped) {
        core::Eigenmode as_eigenmode;
        as_eigenmode.eigenvalue = mode.eigenvalue;
        as_eigenmode.frequency_Hz = mode.frequency_Hz;
        as_eigenmode.damping_ratio = mode.damping_ratio;
        as_eigenmode.shape = normalised(mode.shape);
        damped.push_back(eigenmode_json(as_eigenmode));
    }
    return {
        {"strip_stiffness_GN_per_m", quantity_json(strip_stiffness, units::giganewton_per_metre)},
        {"natural_frequencies_Hz", std::move(frequencies)},
        {"natural_mode_shapes", std::move(shapes)},
        {"damped_modes", std::move(damped)},
    };
}

nlohmann::json critical_speed_summary_json(const core::CriticalSpeedResult& result) {
    const bool found = result.status == core::CriticalSpeedStatus::found;
    const bool mode_known = found || result.status == core::CriticalSpeedStatus::unstable_at_lower_bound;
    return {
        {"status", core::to_string(result.status)},
        {"critical_speed_m_per_s", found ? quantity_json(result.critical_speed, units::metre_per_second) : nullptr},
        {"unstable_mode_frequency_Hz",
         mode_known ? quantity_json(result.unstable_mode.frequency_Hz, units::hertz) : nullptr},
        {"unstable_mode_chatter_type",
         mode_known ? nlohmann::json(core::to_string(result.unstable_mode.chatter.type)) : nullptr},
        {"unstable_mode_chatter_band",
         mode_known ? nlohmann::json(core::to_string(result.unstable_mode.chatter.band)) : nullptr},
    };
}

nlohmann::json critical_speed_json(const core::CriticalSpeedResult& result) {
    const bool found = result.status == core::CriticalSpeedStatus::found;
    const bool mode_known = found || result.status == core::CriticalSpeedStatus::unstable_at_lower_bound;
    nlohmann::json scan = nlohmann::json::array();
    for (const core::SpeedStability& point : result.scan) {
        const bool known = linearised(point);
        scan.push_back({
            {"speed_m_per_s", quantity_json(point.speed, units::metre_per_second)},
            {"stable", known ? nlohmann::json(point.stable) : nlohmann::json(nullptr)},
            {"max_growth_rate_per_s", known ? quantity_json(point.max_real_part, units::per_second) : nullptr},
            {"steady_status", core::to_string(point.steady_status)},
        });
    }
    nlohmann::json branches = nlohmann::json::array();
    for (const core::DampingBranch& branch : result.branches) {
        branches.push_back({
            {"speed_m_per_s", quantities_json(branch.speed, units::metre_per_second)},
            {"frequency_Hz", quantities_json(branch.frequency_Hz, units::hertz)},
            {"damping_ratio", quantities_json(branch.damping_ratio, units::one)},
        });
    }
    return {
        {"status", core::to_string(result.status)},
        {"critical_speed_m_per_s", found ? quantity_json(result.critical_speed, units::metre_per_second) : nullptr},
        {"unstable_mode", nullable_mode(mode_known, result.unstable_mode)},
        {"scan", std::move(scan)},
        {"damping_branches", std::move(branches)},
    };
}

}  // namespace rollgap::api
