#pragma once
// Options and results of the linear stability analysis and the critical-speed search
// (docs/model.md §7.3): the analysis "stability", and the "critical_speed" member of the options of
// "sweep" and "evaluate".
//
// Options (units in the names; defaults from core::CriticalSpeedOptions):
//   speed_min_m_per_s   1     [0.01, 100], below speed_max_m_per_s
//   speed_max_m_per_s   60    [0.01, 100]
//   speed_step_m_per_s  0.5   (0, 0.5], at most max_scan_points scan speeds
//   relative_tolerance  1e-4  [1e-8, 0.01], of the critical speed
//   critical_speed      true  (stability only) whether to search the critical speed at all
//   detail              "full" (stability only) "full" | "summary", see read_detail

#include <complex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/options_reader.h"
#include "api/result_table.h"
#include "core/stand_structure.h"
#include "core/stability.h"

namespace rollgap::api {

// One search evaluates the stability at every scan speed; this bounds its work (the default
// range 1-60 m/s at 0.5 m/s is 119 speeds).
inline constexpr int max_scan_points = 4000;

enum class Detail { full, summary };

struct StabilityOptions {
    core::CriticalSpeedOptions search;  // `threads` is the service's choice, not an option
    bool critical_speed = true;
    Detail detail = Detail::full;
};

StabilityOptions stability_options_from_json(const nlohmann::json& options,
                                             const std::string& pointer, FieldErrors& errors);
// The same members read by a reader of a larger options object (the tandem mill's), and their
// names.
StabilityOptions read_stability_options(const OptionsReader& reader);
std::span<const std::string_view> stability_option_members();
nlohmann::json stability_options_json(const StabilityOptions& options);

// The search options alone (the "critical_speed" member of sweep and evaluate options).
core::CriticalSpeedOptions critical_speed_options_from_json(const nlohmann::json& options,
                                                            const std::string& pointer,
                                                            FieldErrors& errors);
nlohmann::json critical_speed_options_json(const core::CriticalSpeedOptions& options);
// The same members read by a reader of a larger options object (speed_limit's), and their names.
void read_critical_speed_search(const OptionsReader& reader, core::CriticalSpeedOptions& search);
std::span<const std::string_view> critical_speed_search_members();

// The number of scan speeds core::critical_speed evaluates for these options.
int scan_point_count(const core::CriticalSpeedOptions& options);

// How much of a large result to return: "full" (the default) or "summary", the headline
// figures and modes without the critical-speed scan and damping branches (nor, in evaluate, the
// distributions, the amplitude windows and the time series).
void read_detail(const OptionsReader& reader, Detail& detail);
nlohmann::json detail_json(Detail detail);

// The stability analysis' result: the linearisation at the scenario's speed, the modes of the
// stack (without a steady bite: none) and the critical-speed search (if asked for).
struct StabilityReport {
    core::SpeedStability at_speed;
    std::optional<core::ModalAnalysis> modal;
    std::optional<core::CriticalSpeedResult> critical;
    Detail detail = Detail::full;
};
nlohmann::json stability_result_json(const StabilityReport& report);

// The short forms: evaluate's "stability" and "critical_speed", a sweep point's figures.
nlohmann::json speed_stability_summary_json(const core::SpeedStability& stability);
nlohmann::json critical_speed_summary_json(const core::CriticalSpeedResult& result);
nlohmann::json critical_speed_json(const core::CriticalSpeedResult& result,
                                   Detail detail = Detail::full);

// The tables that write them (result_table.h) and their OpenAPI components.
const ResultTable<core::Eigenmode>& eigenmode_table();
const ResultTable<std::complex<double>>& eigenvalue_table();
const ResultTable<core::SpeedStability>& scan_point_table();
const ResultTable<core::DampingBranch>& damping_branch_table();
const ResultTable<core::SpeedStability>& speed_stability_summary_table();
const ResultTable<core::CriticalSpeedResult>& critical_speed_summary_table();
// Members shared with a sweep point: status and critical_speed_m_per_s; the unstable mode's
// frequency under `name`.
std::vector<Member<core::CriticalSpeedResult>> critical_speed_head_members();
Member<core::CriticalSpeedResult> unstable_frequency_member(std::string_view name);
// The chatter type and band of the mode that goes unstable, under these names.
std::vector<Member<core::CriticalSpeedResult>> unstable_chatter_members(std::string_view type_name,
                                                                        std::string_view band_name);
const ResultTable<core::Eigenmode>& chatter_mode_table();
// A sweep point's or a map cell's figures: status, critical_speed_m_per_s, and the frequency_Hz,
// chatter_type and chatter_band of the mode that goes unstable.
std::vector<Member<core::CriticalSpeedResult>> crossing_members();
const ResultTable<StabilityReport>& stability_result_table();
std::vector<ResultSchema> stability_result_schemas();

}  // namespace rollgap::api
