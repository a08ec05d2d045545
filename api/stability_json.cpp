// Writing the stability analysis' result (api/stability_json.h): eigenvalues and modes at a
// speed, the critical-speed search, the scan; the options reader is in stability_options_json.cpp.
#include "api/option_names.h"
#include "api/stability_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <string_view>
#include <vector>

#include "api/chatter_json.h"
#include "api/options_reader.h"
#include "api/result_table.h"
#include "api/quantity_json.h"
#include "api/scenario_schema.h"
#include "api/text.h"

namespace rollgap::api {
namespace {

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
    return stability.steady_status == core::BiteStatus::ok &&
           stability.status == core::DynamicsStatus::ok;
}

std::string stability_status(const core::SpeedStability& stability) {
    if (stability.steady_status != core::BiteStatus::ok) return "no_steady_state";
    return core::to_string(stability.status);
}

}  // namespace

namespace {

using core::SpeedStability;

nlohmann::json status_schema() {
    return enum_schema(
        {"ok", "no_steady_state", "contact_lost", "skidding", "slack_strip", "solver_failure"});
}
nlohmann::json steady_status_schema() {
    return enum_schema({"ok", "skidding", "contact_lost", "solver_failure"});
}
nlohmann::json shape_schema() { return array_schema(number_schema(units::one)); }
constexpr std::string_view shape_text =
    "Relative displacements of the six masses m1..m6 (docs/model.md §5), largest magnitude 1.";

bool steady(const SpeedStability& stability) {
    return stability.steady_status == core::BiteStatus::ok;
}

nlohmann::json speed_figure(const SpeedStability& stability, double value, Unit unit) {
    return linearised(stability) ? quantity_json(value, unit) : nlohmann::json(nullptr);
}

// The members a short answer has (evaluate's "stability", and the head of stability's result).
std::vector<Member<SpeedStability>> summary_members() {
    return {
        {"status",
         "`ok`: linearised. `no_steady_state`: the steady bite skids or loses contact (steady_status says "
         "which). Otherwise why the linearisation failed; every figure is then null.",
         status_schema(),
         [](const SpeedStability& s) { return nlohmann::json(stability_status(s)); }},
        {"steady_status", "The status of the steady bite at this speed.", steady_status_schema(),
         [](const SpeedStability& s) { return nlohmann::json(core::to_string(s.steady_status)); }},
        {"stable", "Whether every eigenvalue has a negative real part.", boolean_schema(true),
         [](const SpeedStability& s) {
             return linearised(s) ? nlohmann::json(s.stable) : nlohmann::json(nullptr);
         }},
        {"max_growth_rate_per_s", "The largest real part over all eigenvalues.",
         number_schema(units::per_second),
         [](const SpeedStability& s) {
             return speed_figure(s, s.max_real_part, units::per_second);
         }},
        {"strip_stiffness_GN_per_m", "The strip spring k4 of the bite (docs/model.md §6).",
         number_schema(units::giganewton_per_metre),
         [](const SpeedStability& s) {
             // k4 is known once the steady bite is, even if the linearisation then failed.
             return steady(s) && s.strip_stiffness > 0.0
                        ? quantity_json(s.strip_stiffness, units::giganewton_per_metre)
                        : nlohmann::json(nullptr);
         }},
        {"least_damped_mode", "The oscillatory mode with the largest growth rate; null if none.",
         ref_schema("ChatterMode", true),
         [](const SpeedStability& s) {
             return linearised(s) && !s.oscillatory.empty()
                        ? chatter_mode_table().write(s.least_damped)
                        : nlohmann::json(nullptr);
         }},
    };
}

std::vector<Member<SpeedStability>> at_speed_members() {
    std::vector<Member<SpeedStability>> members = summary_members();
    members.push_back({"speed_m_per_s", "The roll speed of the linearisation.",
                       number_schema(units::metre_per_second), [](const SpeedStability& s) {
                           return quantity_json(s.speed, units::metre_per_second);
                       }});
    members.push_back({"force_kN", "The steady roll force.", number_schema(units::kilonewton),
                       [](const SpeedStability& s) {
                           return steady(s) ? quantity_json(s.force, units::kilonewton)
                                            : nlohmann::json(nullptr);
                       }});
    members.push_back({"oscillatory_modes", "The oscillatory modes (Im > 0), ascending frequency.",
                       array_schema(ref_schema("ChatterMode")), [](const SpeedStability& s) {
                           nlohmann::json modes = nlohmann::json::array();
                           for (const core::Eigenmode& mode : s.oscillatory)
                               modes.push_back(chatter_mode_table().write(mode));
                           return modes;
                       }});
    members.push_back(
        {"eigenvalues",
         "Every eigenvalue, least damped first, conjugates by ascending imaginary part; empty unless "
         "status is ok.",
         array_schema(ref_schema("Eigenvalue")), [](const SpeedStability& s) {
             // Deterministic whatever order the eigensolver returns them in.
             std::vector<std::complex<double>> eigenvalues = s.eigenvalues;
             std::sort(eigenvalues.begin(), eigenvalues.end(), [](const auto& a, const auto& b) {
                 return a.real() != b.real() ? a.real() > b.real() : a.imag() < b.imag();
             });
             nlohmann::json values = nlohmann::json::array();
             if (!linearised(s)) return values;
             for (const auto& lambda : eigenvalues)
                 values.push_back(eigenvalue_table().write(lambda));
             return values;
         }});
    return members;
}

struct Structure {
    const core::ModalAnalysis& modal;
    double strip_stiffness;
};

struct CriticalSpeedView {
    const core::CriticalSpeedResult& result;
    Detail detail;
};

bool found(const core::CriticalSpeedResult& result) {
    return result.status == core::CriticalSpeedStatus::found;
}
bool mode_known(const core::CriticalSpeedResult& result) {
    return found(result) || result.status == core::CriticalSpeedStatus::unstable_at_lower_bound;
}

nlohmann::json critical_status_schema() {
    return enum_schema({"found", "stable_in_range", "unstable_at_lower_bound", "no_steady_state"});
}
constexpr std::string_view critical_status_text =
    "`found`: the stand chatters above critical_speed_m_per_s. `stable_in_range`: stable over the whole "
    "search range. `unstable_at_lower_bound`: already unstable at speed_min_m_per_s. `no_steady_state`: no "
    "speed of the range has a steady bite.";

const ResultTable<Structure>& structure_table() {
    static const ResultTable<Structure> table{
        "StructureModes",
        "Natural and damped modes of the stack with the strip spring k4 (not the bite dynamics); shapes "
        "normalised to their largest component 1.",
        {
            {"strip_stiffness_GN_per_m", "The strip spring k4 used.",
             number_schema(units::giganewton_per_metre),
             [](const Structure& s) {
                 return quantity_json(s.strip_stiffness, units::giganewton_per_metre);
             }},
            {"natural_frequencies_Hz", "Undamped natural frequencies, ascending.",
             array_schema(number_schema(units::hertz)),
             [](const Structure& s) {
                 nlohmann::json values = nlohmann::json::array();
                 for (const core::NaturalMode& mode : s.modal.natural)
                     values.push_back(quantity_json(mode.frequency_Hz, units::hertz));
                 return values;
             }},
            {"natural_mode_shapes", "The undamped mode shapes, one per natural frequency (m1..m6).",
             array_schema(shape_schema()),
             [](const Structure& s) {
                 nlohmann::json shapes = nlohmann::json::array();
                 for (const core::NaturalMode& mode : s.modal.natural)
                     shapes.push_back(shape_json(normalised(mode.shape)));
                 return shapes;
             }},
            {"damped_modes", "The damped oscillatory modes of the stack, ascending frequency.",
             array_schema(ref_schema("Eigenmode")),
             [](const Structure& s) {
                 nlohmann::json damped = nlohmann::json::array();
                 for (const core::DampedMode& mode : s.modal.damped) {
                     core::Eigenmode as_eigenmode;
                     as_eigenmode.eigenvalue = mode.eigenvalue;
                     as_eigenmode.frequency_Hz = mode.frequency_Hz;
                     as_eigenmode.damping_ratio = mode.damping_ratio;
                     as_eigenmode.shapes = {normalised(mode.shape)};
                     damped.push_back(eigenmode_table().write(as_eigenmode));
                 }
                 return damped;
             }},
        }};
    return table;
}

const ResultTable<CriticalSpeedView>& critical_speed_table() {
    static const ResultTable<CriticalSpeedView> table{
        "CriticalSpeed",
        "The critical-speed search: a scan of the speed range, refined where the stability changes. With "
        "options.detail \"summary\" the scan and the damping branches are left out.",
        [] {
            std::vector<Member<CriticalSpeedView>> members = lift<CriticalSpeedView>(
                critical_speed_head_members(),
                [](const CriticalSpeedView& v) -> const core::CriticalSpeedResult& {
                    return v.result;
                });
            std::vector<Member<CriticalSpeedView>> rest{
                {"unstable_mode",
                 "The mode whose eigenvalue crosses zero there; null unless found or unstable_at_lower_bound.",
                 ref_schema("ChatterMode", true),
                 [](const CriticalSpeedView& v) {
                     return mode_known(v.result)
                                ? chatter_mode_table().write(v.result.unstable_mode)
                                : nlohmann::json(nullptr);
                 }},
                {"scan", "The scanned speeds (options.detail \"full\" only).",
                 array_schema(ref_schema("ScanPoint")),
                 [](const CriticalSpeedView& v) {
                     if (v.detail == Detail::summary) return absent();
                     nlohmann::json scan = nlohmann::json::array();
                     for (const SpeedStability& point : v.result.scan)
                         scan.push_back(scan_point_table().write(point));
                     return scan;
                 },
                 true},
                {"damping_branches",
                 "The damping ratio of each oscillatory mode over the scan (options.detail \"full\" only).",
                 array_schema(ref_schema("DampingBranch")),
                 [](const CriticalSpeedView& v) {
                     if (v.detail == Detail::summary) return absent();
                     nlohmann::json branches = nlohmann::json::array();
                     for (const core::DampingBranch& branch : v.result.branches)
                         branches.push_back(damping_branch_table().write(branch));
                     return branches;
                 },
                 true},
            };
            members.insert(members.end(), rest.begin(), rest.end());
            return members;
        }()};
    return table;
}

}  // namespace

std::vector<Member<core::Eigenmode>> eigenmode_members() {
    return {
        {"frequency_Hz", "Damped natural frequency.", number_schema(units::hertz),
         [](const core::Eigenmode& m) { return quantity_json(m.frequency_Hz, units::hertz); }},
        {"damping_ratio", "Damping ratio, negative when the mode grows.", number_schema(units::one),
         [](const core::Eigenmode& m) { return quantity_json(m.damping_ratio, units::one); }},
        {"growth_rate_per_s", "Real part of the eigenvalue.", number_schema(units::per_second),
         [](const core::Eigenmode& m) {
             return quantity_json(m.eigenvalue.real(), units::per_second);
         }},
        {"shape", shape_text, shape_schema(),
         [](const core::Eigenmode& m) { return shape_json(m.shapes.front()); }},
    };
}

const ResultTable<core::Eigenmode>& eigenmode_table() {
    static const ResultTable<core::Eigenmode> table{
        "Eigenmode", "An oscillatory mode of the stack.", eigenmode_members()};
    return table;
}

std::vector<Member<core::Eigenmode>> chatter_type_members(std::string_view type_name,
                                                          std::string_view band_name) {
    return {
        {type_name, chatter_type_text, chatter_type_schema(),
         [](const core::Eigenmode& m) { return nlohmann::json(core::to_string(m.chatter.type)); }},
        {band_name, chatter_band_text, chatter_type_schema(),
         [](const core::Eigenmode& m) { return nlohmann::json(core::to_string(m.chatter.band)); }},
    };
}

// A mode of the coupled model (its shape has phases): with its chatter type (docs/model.md,
// "Chatter type") and the type its frequency band alone suggests.
const ResultTable<core::Eigenmode>& chatter_mode_table() {
    static const ResultTable<core::Eigenmode> table{
        "ChatterMode",
        "An oscillatory mode of the linearised stand and bite, with its chatter type.", [] {
            std::vector<Member<core::Eigenmode>> members = eigenmode_members();
            for (Member<core::Eigenmode>& member :
                 chatter_type_members("chatter_type", "chatter_band")) {
                members.push_back(std::move(member));
            }
            return members;
        }()};
    return table;
}

const ResultTable<std::complex<double>>& eigenvalue_table() {
    static const ResultTable<std::complex<double>> table{
        "Eigenvalue",
        "An eigenvalue of the linearised stand and bite.",
        {
            {"real_per_s", "Real part (growth rate).", number_schema(units::per_second),
             [](const std::complex<double>& l) {
                 return quantity_json(l.real(), units::per_second);
             }},
            {"imag_per_s", "Imaginary part (angular frequency).", number_schema(units::per_second),
             [](const std::complex<double>& l) {
                 return quantity_json(l.imag(), units::per_second);
             }},
        }};
    return table;
}

const ResultTable<core::SpeedStability>& scan_point_table() {
    static const ResultTable<SpeedStability> table{
        "ScanPoint",
        "The stability at one scanned speed.",
        {
            {"speed_m_per_s", "The roll speed.", number_schema(units::metre_per_second),
             [](const SpeedStability& s) {
                 return quantity_json(s.speed, units::metre_per_second);
             }},
            {"stable",
             "Whether every eigenvalue has a negative real part; null without a linearisation.",
             boolean_schema(true),
             [](const SpeedStability& s) {
                 return linearised(s) ? nlohmann::json(s.stable) : nlohmann::json(nullptr);
             }},
            {"max_growth_rate_per_s", "The largest real part over all eigenvalues.",
             number_schema(units::per_second),
             [](const SpeedStability& s) {
                 return speed_figure(s, s.max_real_part, units::per_second);
             }},
            {"steady_status", "The status of the steady bite at this speed.",
             steady_status_schema(),
             [](const SpeedStability& s) {
                 return nlohmann::json(core::to_string(s.steady_status));
             }},
        }};
    return table;
}

const ResultTable<core::DampingBranch>& damping_branch_table() {
    static const ResultTable<core::DampingBranch> table{
        "DampingBranch",
        "One oscillatory mode followed over the scan, columnar (arrays of equal length).",
        {
            {"speed_m_per_s", "The roll speeds.",
             array_schema(number_schema(units::metre_per_second)),
             [](const core::DampingBranch& b) {
                 return quantities_json(b.speed, units::metre_per_second);
             }},
            {"frequency_Hz", "The mode's frequency at each speed.",
             array_schema(number_schema(units::hertz)),
             [](const core::DampingBranch& b) {
                 return quantities_json(b.frequency_Hz, units::hertz);
             }},
            {"damping_ratio", "The mode's damping ratio at each speed.",
             array_schema(number_schema(units::one)),
             [](const core::DampingBranch& b) {
                 return quantities_json(b.damping_ratio, units::one);
             }},
        }};
    return table;
}

const ResultTable<core::SpeedStability>& speed_stability_summary_table() {
    static const ResultTable<SpeedStability> table{
        "StabilitySummary", "The stability of the linearisation at the scenario's speed.",
        summary_members()};
    return table;
}

std::vector<Member<core::CriticalSpeedResult>> critical_speed_head_members() {
    return {
        {"status", critical_status_text, critical_status_schema(),
         [](const core::CriticalSpeedResult& r) {
             return nlohmann::json(core::to_string(r.status));
         }},
        {"critical_speed_m_per_s", "The lowest unstable speed of the range; null unless found.",
         number_schema(units::metre_per_second),
         [](const core::CriticalSpeedResult& r) {
             return found(r) ? quantity_json(r.critical_speed, units::metre_per_second)
                             : nlohmann::json(nullptr);
         }},
    };
}

Member<core::CriticalSpeedResult> unstable_frequency_member(std::string_view name) {
    return {
        name,
        "The frequency of the mode that goes unstable; null unless found or unstable_at_lower_bound.",
        number_schema(units::hertz), [](const core::CriticalSpeedResult& r) {
            return mode_known(r) ? quantity_json(r.unstable_mode.frequency_Hz, units::hertz)
                                 : nlohmann::json(nullptr);
        }};
}

std::vector<Member<core::CriticalSpeedResult>> unstable_chatter_members(
    std::string_view type_name, std::string_view band_name) {
    std::vector<Member<core::CriticalSpeedResult>> members;
    const std::array<std::string_view, 2> texts{
        "The chatter type of the mode that goes unstable (from its shape); null unless found or "
        "unstable_at_lower_bound.",
        "The chatter type the frequency band of the mode that goes unstable suggests; null unless found or "
        "unstable_at_lower_bound."};
    std::vector<Member<core::Eigenmode>> mode_members = chatter_type_members(type_name, band_name);
    for (std::size_t i = 0; i < mode_members.size(); ++i) {
        members.push_back({mode_members[i].name, texts[i], chatter_type_schema(true),
                           [get = mode_members[i].get](const core::CriticalSpeedResult& r) {
                               return mode_known(r) ? get(r.unstable_mode)
                                                    : nlohmann::json(nullptr);
                           }});
    }
    return members;
}

std::vector<Member<core::CriticalSpeedResult>> crossing_members() {
    std::vector<Member<core::CriticalSpeedResult>> members = critical_speed_head_members();
    members.push_back(unstable_frequency_member("frequency_Hz"));
    for (Member<core::CriticalSpeedResult>& member :
         unstable_chatter_members("chatter_type", "chatter_band")) {
        members.push_back(std::move(member));
    }
    return members;
}

const ResultTable<core::CriticalSpeedResult>& critical_speed_summary_table() {
    static const ResultTable<core::CriticalSpeedResult> table{
        "CriticalSpeedSummary", "The outcome of the critical-speed search.", [] {
            std::vector<Member<core::CriticalSpeedResult>> members = critical_speed_head_members();
            members.push_back(unstable_frequency_member("unstable_mode_frequency_Hz"));
            for (Member<core::CriticalSpeedResult>& member : unstable_chatter_members(
                     "unstable_mode_chatter_type", "unstable_mode_chatter_band")) {
                members.push_back(std::move(member));
            }
            return members;
        }()};
    return table;
}

const ResultTable<StabilityReport>& stability_result_table() {
    static const ResultTable<StabilityReport> table{
        "StabilityResult",
        "The linearisation at the scenario's speed, the modes of the stack and the critical chatter speed "
        "(docs/model.md §7.3).",
        [] {
            std::vector<Member<StabilityReport>> members = lift<StabilityReport>(
                at_speed_members(),
                [](const StabilityReport& r) -> const SpeedStability& { return r.at_speed; });
            members.push_back({"structure", "The modes of the stack; null without a steady bite.",
                               ref_schema("StructureModes", true), [](const StabilityReport& r) {
                                   return r.modal.has_value()
                                              ? structure_table().write(
                                                    {*r.modal, r.at_speed.strip_stiffness})
                                              : nlohmann::json(nullptr);
                               }});
            members.push_back(
                {"critical_speed",
                 "The critical-speed search; null when options.critical_speed is false.",
                 ref_schema("CriticalSpeed", true), [](const StabilityReport& r) {
                     return r.critical.has_value()
                                ? critical_speed_table().write({*r.critical, r.detail})
                                : nlohmann::json(nullptr);
                 }});
            return members;
        }()};
    return table;
}

std::vector<ResultSchema> stability_result_schemas() {
    return {result_schema(eigenmode_table()),
            result_schema(chatter_mode_table()),
            result_schema(eigenvalue_table()),
            result_schema(scan_point_table()),
            result_schema(damping_branch_table()),
            result_schema(structure_table()),
            result_schema(critical_speed_table()),
            result_schema(speed_stability_summary_table()),
            result_schema(critical_speed_summary_table()),
            result_schema(stability_result_table())};
}

nlohmann::json stability_result_json(const StabilityReport& report) {
    return stability_result_table().write(report);
}

nlohmann::json speed_stability_summary_json(const core::SpeedStability& stability) {
    return speed_stability_summary_table().write(stability);
}

nlohmann::json critical_speed_summary_json(const core::CriticalSpeedResult& result) {
    return critical_speed_summary_table().write(result);
}

nlohmann::json critical_speed_json(const core::CriticalSpeedResult& result, Detail detail) {
    return critical_speed_table().write({result, detail});
}

}  // namespace rollgap::api
