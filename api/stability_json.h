#pragma once
// Options and results of the linear stability analysis and the critical-speed search
// (MODEL.md §7.3): the analysis "stability", and the "critical_speed" member of the options of
// "sweep" and "evaluate".
//
// Options (units in the names; defaults from core::CriticalSpeedOptions):
//   speed_min_m_per_s   1     [0.01, 100], below speed_max_m_per_s
//   speed_max_m_per_s   60    [0.01, 100]
//   speed_step_m_per_s  0.5   (0, 0.5], at most max_scan_points scan speeds
//   relative_tolerance  1e-4  [1e-8, 0.01], of the critical speed
//   critical_speed      true  (stability only) whether to search the critical speed at all

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "core/mill_structure.h"
#include "core/stability.h"

namespace rollgap::api {

// One search evaluates the stability at every scan speed; this bounds its work (the default
// range 1-60 m/s at 0.5 m/s is 119 speeds).
inline constexpr int max_scan_points = 4000;

struct StabilityOptions {
    core::CriticalSpeedOptions search;  // `threads` is the service's choice, not an option
    bool critical_speed = true;
};

StabilityOptions stability_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                             FieldErrors& errors);
nlohmann::json stability_options_json(const StabilityOptions& options);

// The search options alone (the "critical_speed" member of sweep and evaluate options).
core::CriticalSpeedOptions critical_speed_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                                            FieldErrors& errors);
nlohmann::json critical_speed_options_json(const core::CriticalSpeedOptions& options);

// The number of scan speeds core::critical_speed evaluates for these options.
int scan_point_count(const core::CriticalSpeedOptions& options);

// {"frequency_Hz", "damping_ratio", "growth_rate_per_s", "shape": [m1..m6, largest 1]}
nlohmann::json eigenmode_json(const core::Eigenmode& mode);

// The linearisation at one speed: {"speed_m_per_s", "status", "steady_status", "stable",
// "max_growth_rate_per_s", "strip_stiffness_GN_per_m", "force_kN", "least_damped_mode",
// "oscillatory_modes" (each mode also with "chatter_type" and "chatter_band"), "eigenvalues": [{"real_per_s", "imag_per_s"}]}. "status" is "ok",
// "no_steady_state" (the steady bite skids or loses contact: "steady_status" says which) or why
// the linearisation failed; without "ok" every figure is null.
nlohmann::json speed_stability_json(const core::SpeedStability& stability);

// The same, short (evaluate): status, steady_status, stable, max_growth_rate_per_s,
// strip_stiffness_GN_per_m, least_damped_mode.
nlohmann::json speed_stability_summary_json(const core::SpeedStability& stability);

// Natural and damped modes of the stack with the strip spring k4 (not the bite dynamics):
// {"strip_stiffness_GN_per_m", "natural_frequencies_Hz": [...], "natural_mode_shapes": [[m1..m6]...],
//  "damped_modes": [{eigenmode}]}; shapes normalised to their largest component 1.
nlohmann::json structure_modes_json(const core::ModalAnalysis& modal, double strip_stiffness);

// {"status", "critical_speed_m_per_s", "unstable_mode", "scan": [{"speed_m_per_s", "stable",
// "max_growth_rate_per_s", "steady_status"}], "damping_branches": [{"speed_m_per_s": [...],
// "frequency_Hz": [...], "damping_ratio": [...]}]}. The critical speed is null unless found;
// the unstable mode is null unless found or unstable_at_lower_bound.
nlohmann::json critical_speed_json(const core::CriticalSpeedResult& result);

// {"status", "critical_speed_m_per_s", "unstable_mode_frequency_Hz", "unstable_mode_chatter_type",
//  "unstable_mode_chatter_band"}
nlohmann::json critical_speed_summary_json(const core::CriticalSpeedResult& result);

}  // namespace rollgap::api
