#include "api/tandem_result_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <numbers>
#include <string_view>

#include "api/chatter_json.h"
#include "api/quantity_json.h"
#include "api/text.h"
#include "core/chatter_type.h"

namespace rollgap::api {
namespace {

using nlohmann::json;
using namespace units;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

json numbers_schema(Unit unit) { return array_schema(number_schema(unit)); }

// ---- the steady state, per stand ------------------------------------------------------------

struct StandRow {
    int index = 0;
    const core::MillStandState* state = nullptr;
    double entry_thickness = 0.0;
    double exit_thickness = 0.0;
    double mark_spacing = nan;  // u2 / f of the rightmost root, m
};

const ResultTable<StandRow>& stand_table() {
    static const ResultTable<StandRow> table{
        "TandemStand",
        "One stand of the mill in its steady state (docs/model.md §12.3).",
        {
            {"stand", "The stand's number, 1 at the entry.", stand_number_schema(false),
             [](const StandRow& r) { return stand_number(r.index); }},
            {"status",
             "ok, or why this stand has no steady state: skidding (no neutral point in the "
             "bite), contact_lost, solver_failure.",
             enum_schema({"ok", "skidding", "contact_lost", "solver_failure"}),
             [](const StandRow& r) { return core::to_string(r.state->status); }},
            {"entry_thickness_mm", "Strip thickness entering the stand, y1.",
             number_schema(millimetre),
             [](const StandRow& r) { return quantity_json(r.entry_thickness, millimetre); }},
            {"exit_thickness_mm", "Strip thickness leaving the stand, y2.",
             number_schema(millimetre),
             [](const StandRow& r) { return quantity_json(r.exit_thickness, millimetre); }},
            {"roll_speed_m_per_s",
             "Work-roll surface speed v: the mill speed at the last stand, from the mass flow at "
             "the others.",
             number_schema(metre_per_second),
             [](const StandRow& r) {
                 return quantity_json(r.state->roll_speed, metre_per_second);
             }},
            {"entry_speed_m_per_s", "Strip speed entering the stand, u1.",
             number_schema(metre_per_second),
             [](const StandRow& r) {
                 return quantity_json(r.state->entry_speed, metre_per_second);
             }},
            {"exit_speed_m_per_s", "Strip speed leaving the stand, u2 (= the next stand's u1).",
             number_schema(metre_per_second),
             [](const StandRow& r) {
                 return quantity_json(r.state->exit_speed, metre_per_second);
             }},
            {"forward_slip", "Forward slip (u2 - v) / v.", number_schema(one),
             [](const StandRow& r) { return quantity_json(r.state->forward_slip, one); }},
            {"force_kN", "Roll force P over the strip width.", number_schema(kilonewton),
             [](const StandRow& r) { return quantity_json(r.state->force, kilonewton); }},
            {"torque_kN_m", "Rolling torque per work roll.", number_schema(kilonewton_metre),
             [](const StandRow& r) { return quantity_json(r.state->torque, kilonewton_metre); }},
            {"power_kW", "Rolling power of both work rolls.", number_schema(kilowatt),
             [](const StandRow& r) { return quantity_json(r.state->power, kilowatt); }},
            {"inlet_film_um", "Inlet film thickness h0.", number_schema(micrometre),
             [](const StandRow& r) { return quantity_json(r.state->inlet_film, micrometre); }},
            {"neutral_point_mm", "Neutral point x_n, from the exit.", number_schema(millimetre),
             [](const StandRow& r) { return quantity_json(r.state->neutral_point, millimetre); }},
            {"back_tension_MPa", "Back tension stress sigma_b = T / y1 of the span behind.",
             number_schema(megapascal),
             [](const StandRow& r) { return quantity_json(r.state->back_tension, megapascal); }},
            {"front_tension_MPa", "Front tension stress sigma_f = T / y2 of the span ahead.",
             number_schema(megapascal),
             [](const StandRow& r) { return quantity_json(r.state->front_tension, megapascal); }},
            {"back_tension_force_kN", "Strip force of the span behind, T w.",
             number_schema(kilonewton),
             [](const StandRow& r) {
                 return quantity_json(r.state->back_tension_force, kilonewton);
             }},
            {"front_tension_force_kN", "Strip force of the span ahead, T w.",
             number_schema(kilonewton),
             [](const StandRow& r) {
                 return quantity_json(r.state->front_tension_force, kilonewton);
             }},
            {"chatter_mark_spacing_mm",
             "Spacing u2 / f of the marks the rightmost root would leave on this stand's exit "
             "strip (null without a root).",
             number_schema(millimetre),
             [](const StandRow& r) { return quantity_json(r.mark_spacing, millimetre); }},
        }};
    return table;
}

struct SteadyView {
    const core::MillSteadyState* steady = nullptr;
    std::vector<StandRow> rows;
};

const ResultTable<SteadyView>& steady_table() {
    static const ResultTable<SteadyView> table{
        "TandemSteadyState",
        "The mill's steady state at its speed: the pass schedule (docs/model.md §12.3).",
        {
            {"status",
             "ok; no_steady_state when a stand skids, loses contact or fails (failed_stand names "
             "it) or, in speeds mode, a span would go slack (slack_span names it).",
             enum_schema({"ok", "no_steady_state", "invalid"}),
             [](const SteadyView& v) { return core::to_string(v.steady->status); }},
            {"message", "Why there is no steady state; empty when ok.", string_schema(),
             [](const SteadyView& v) { return std::string(v.steady->message); }},
            {"failed_stand", "The stand without a steady state, or null.",
             stand_number_schema(true),
             [](const SteadyView& v) { return stand_number(v.steady->stand); }},
            {"slack_span",
             "speeds mode: the interstand span (1 = between stands 1 and 2) that the given roll "
             "speeds would drive slack, or null.",
             stand_number_schema(true),
             [](const SteadyView& v) {
                 return v.steady->span >= 1 ? json(v.steady->span) : json(nullptr);
             }},
            {"mass_flow_m2_per_s", "Mass flow per width Q = u2 y2 of the last stand.",
             number_schema(square_metre_per_second),
             [](const SteadyView& v) {
                 return quantity_json(v.steady->mass_flow, square_metre_per_second);
             }},
            {"mass_flow_residual", "max over stands of |u2 y2 - Q| / Q: the schedule's accuracy.",
             number_schema(one),
             [](const SteadyView& v) { return quantity_json(v.steady->mass_flow_residual, one); }},
            {"stands", "Every stand, from the entry.", array_schema(ref_schema("TandemStand")),
             [](const SteadyView& v) {
                 json rows = json::array();
                 for (const StandRow& row : v.rows) rows.push_back(stand_table().write(row));
                 return rows;
             }},
        }};
    return table;
}

// ---- validity, a described root, a crossing -------------------------------------------------

const ResultTable<core::CrossingValidity>& validity_table() {
    static const ResultTable<core::CrossingValidity> table{
        "TandemValidity",
        "Whether a root's frequency lies inside the model's range (docs/model.md §12.7).",
        {
            {"valid", "Both the spring law and the quasi-static bite hold.", boolean_schema(),
             [](const core::CrossingValidity& v) { return v.valid(); }},
            {"spring_law_valid",
             "Every interstand span's spring-law stiffness error is at most 25 % (else use "
             "segments: /tandem/spans/model, which carries strip waves; under segments the law "
             "is judged on one segment of length L / n).",
             boolean_schema(), [](const core::CrossingValidity& v) { return v.spring_law_valid; }},
            {"quasi_static_bite_valid",
             "Every stand's bite transit time is at most 0.2 of the period.", boolean_schema(),
             [](const core::CrossingValidity& v) { return v.quasi_static_bite_valid; }},
            {"span_wave_number", "omega L / c per interstand span (c = sqrt(E / rho)).",
             numbers_schema(one),
             [](const core::CrossingValidity& v) {
                 return quantities_json(v.span_wave_number, one);
             }},
            {"spring_law_error",
             "1 - x / tan x per interstand span, x = omega L / c (under segments one segment's, "
             "x = omega L / (n c)).",
             numbers_schema(one),
             [](const core::CrossingValidity& v) {
                 return quantities_json(v.spring_law_error, one);
             }},
            {"bite_transit_ratio", "Bite transit time over the period, (x_w / u1) f, per stand.",
             numbers_schema(one),
             [](const core::CrossingValidity& v) {
                 return quantities_json(v.bite_transit_ratio, one);
             }},
        }};
    return table;
}

// The members a described root and a crossing share.
std::vector<Member<core::MillCrossing>> crossing_description_members(
    std::string_view sensitivity_description) {
    return {
        {"frequency_Hz", "Frequency of the root (delay_independent: where the margin peaks).",
         number_schema(hertz),
         [](const core::MillCrossing& c) {
             return c.frequency_Hz > 0.0 ? quantity_json(c.frequency_Hz, hertz) : json(nullptr);
         }},
        {"moving_stand", "The stand that moves most (the largest participation).",
         stand_number_schema(true),
         [](const core::MillCrossing& c) { return stand_number(c.moving_stand); }},
        {"feeding_stand",
         "The stand whose bite feeds the vibration most (the largest bite-gain sensitivity): "
         "where a change of the bite helps most.",
         stand_number_schema(true),
         [](const core::MillCrossing& c) { return stand_number(c.feeding_stand); }},
        {"participation", "Per stand: its share of the motion, mass-weighted, summing to 1.",
         numbers_schema(one),
         [](const core::MillCrossing& c) { return quantities_json(c.participation, one); }},
        {"feeding_sensitivity", sensitivity_description, numbers_schema(one),
         [](const core::MillCrossing& c) { return quantities_json(c.feeding_sensitivity, one); }},
        {"band", std::string_view(chatter_band_text), chatter_type_schema(true),
         [](const core::MillCrossing& c) {
             return c.frequency_Hz > 0.0 ? json(core::to_string(c.band)) : json(nullptr);
         }},
        {"chatter_type",
         "The chatter type from the shape of the moving stand's six masses in this motion "
         "(docs/model.md, \"Chatter type\", as a single stand's mode): `third_octave`, the roll "
         "packages move against each other and the gap breathes; `fifth_octave`, the work rolls "
         "vibrate against their back-up rolls; `other`, the motion hardly changes the gap. "
         "`band` is the type the frequency alone suggests.",
         chatter_type_schema(true),
         [](const core::MillCrossing& c) {
             return c.frequency_Hz > 0.0 ? json(core::to_string(c.chatter.type)) : json(nullptr);
         }},
        {"validity", "Whether the root lies inside the model's range.",
         ref_schema("TandemValidity", true),
         [](const core::MillCrossing& c) {
             return c.frequency_Hz > 0.0 ? validity_table().write(c.validity) : json(nullptr);
         }},
    };
}

const ResultTable<core::MillRootDescription>& root_table() {
    static const ResultTable<core::MillRootDescription> table = [] {
        std::vector<Member<core::MillRootDescription>> members{
            {"growth_rate_per_s", "Real part of the root: growth (> 0) or decay rate.",
             number_schema(per_second),
             [](const core::MillRootDescription& r) {
                 return quantity_json(r.s.real(), per_second);
             }},
            {"damping_ratio", "-Re / |s|: negative while the root grows.", number_schema(one),
             [](const core::MillRootDescription& r) {
                 return quantity_json(-r.s.real() / std::abs(r.s), one);
             }},
            {"verified", "No root lies right of it (the argument-principle count).",
             boolean_schema(), [](const core::MillRootDescription& r) { return r.verified; }},
        };
        for (auto& member : lift<core::MillRootDescription, core::MillCrossing>(
                 crossing_description_members(
                     "Per stand: d(growth rate)/d kappa with the stand's bite Jacobian scaled "
                     "by (1 + kappa), 1/s per unit kappa."),
                 [](const core::MillRootDescription& r) -> const core::MillCrossing& {
                     return r.described;
                 }))
            members.push_back(std::move(member));
        return ResultTable<core::MillRootDescription>{
            "TandemRoot",
            "The rightmost root of the mill with its nominal transport delays, by stand "
            "(docs/model.md §12.6-12.7).",
            std::move(members)};
    }();
    return table;
}

const ResultTable<core::MillCrossing>& crossing_table() {
    static const ResultTable<core::MillCrossing> table = [] {
        std::vector<Member<core::MillCrossing>> members{
            {"kind",
             "frozen: A0 crosses (the tension path alone); delay_independent: A0 unstable or "
             "rho >= 1 (some set of delays destabilises the mill: the robust limit); "
             "nominal_delay: a root with the actual delays crosses (first_any: of any frequency).",
             enum_schema({"frozen", "delay_independent", "nominal_delay"}),
             [](const core::MillCrossing& c) { return core::to_string(c.kind); }},
            {"status",
             "found; stable_in_range; unstable_at_lower_bound; no_steady_state (the schedule "
             "has no steady state in the range).",
             enum_schema({"found", "stable_in_range", "unstable_at_lower_bound", "no_steady_state",
                          "cancelled"}),
             [](const core::MillCrossing& c) { return core::to_string(c.status); }},
            {"speed_m_per_s", "The mill speed of the crossing (null unless found).",
             number_schema(metre_per_second),
             [](const core::MillCrossing& c) {
                 return c.status == core::CriticalSpeedStatus::found ||
                                c.status == core::CriticalSpeedStatus::unstable_at_lower_bound
                            ? quantity_json(c.speed, metre_per_second)
                            : json(nullptr);
             }},
            {"lobe_period_m_per_s",
             "nominal_delay: the lobe period V / (f tau_max), the speed between neighbouring "
             "crossings of the delay lobes; null for the others.",
             number_schema(metre_per_second),
             [](const core::MillCrossing& c) {
                 return c.kind == core::MillCrossingKind::nominal_delay && c.lobe_period > 0.0
                            ? quantity_json(c.lobe_period, metre_per_second)
                            : json(nullptr);
             }},
        };
        for (auto& member : crossing_description_members(
                 "Per stand: d(growth)/d kappa with the stand's bite Jacobian scaled by "
                 "(1 + kappa): the crossing root's growth rate in 1/s (delay_independent: rho "
                 "itself, dimensionless)."))
            members.push_back(std::move(member));
        return ResultTable<core::MillCrossing>{
            "TandemCrossing", "A critical mill speed (docs/model.md §12.7).", std::move(members)};
    }();
    return table;
}

const ResultTable<core::MillCriticalSpeeds>& critical_table() {
    static const ResultTable<core::MillCriticalSpeeds> table{
        "TandemCriticalSpeeds",
        "The mill's three critical speeds and the headline (docs/model.md §12.7).",
        {
            {"headline",
             "The lowest crossing inside the model's range (spring-law error <= 25 %, bite "
             "transit <= 0.2 of the period); null when none is.",
             enum_schema({"frozen", "delay_independent", "nominal_delay"}, true),
             [](const core::MillCriticalSpeeds& c) {
                 constexpr std::array<const char*, 3> names{"frozen", "delay_independent",
                                                            "nominal_delay"};
                 return c.headline < 0 ? json(nullptr)
                                       : json(names[static_cast<std::size_t>(c.headline)]);
             }},
            {"critical_speed_m_per_s", "The headline's speed; null when there is none.",
             number_schema(metre_per_second),
             [](const core::MillCriticalSpeeds& c) {
                 const core::MillCrossing* all[] = {&c.frozen, &c.delay_independent,
                                                    &c.nominal_delay};
                 return c.headline < 0 ? json(nullptr)
                                       : quantity_json(all[c.headline]->speed, metre_per_second);
             }},
            {"outside_range_below",
             "Crossings below the headline (all, when none is valid) whose root lies outside the "
             "model's range: warnings, reported with their flags, never dropped.",
             array_schema(enum_schema({"frozen", "delay_independent", "nominal_delay"})),
             [](const core::MillCriticalSpeeds& c) {
                 json kinds = json::array();
                 for (const core::MillCrossingKind kind : c.outside_range_below)
                     kinds.push_back(core::to_string(kind));
                 return kinds;
             }},
            {"frozen", "A0 crosses: the tension path alone.", ref_schema("TandemCrossing"),
             [](const core::MillCriticalSpeeds& c) { return crossing_table().write(c.frozen); }},
            {"delay_independent", "The robust limit: some set of delays destabilises the mill.",
             ref_schema("TandemCrossing"),
             [](const core::MillCriticalSpeeds& c) {
                 return crossing_table().write(c.delay_independent);
             }},
            {"nominal_delay",
             "The first root with the actual delays inside the model's band (0 < f <= the "
             "highest frequency the model's range admits at that speed) to cross.",
             ref_schema("TandemCrossing"),
             [](const core::MillCriticalSpeeds& c) {
                 return crossing_table().write(c.nominal_delay);
             }},
            {"first_any",
             "The first root with the actual delays of any frequency to cross (kind "
             "nominal_delay): often a span's or a stand's upper mode outside the model's range; "
             "reported, never a headline.",
             ref_schema("TandemCrossing"),
             [](const core::MillCriticalSpeeds& c) { return crossing_table().write(c.first_any); }},
        }};
    return table;
}

// ---- stability at the mill speed ------------------------------------------------------------

// A frozen mode: an oscillatory eigenvalue of A0.
const ResultTable<core::Eigenmode>& frozen_mode_table() {
    static const ResultTable<core::Eigenmode> table{
        "TandemFrozenMode",
        "An oscillatory eigenvalue of the frozen mill A0 (tension coupling only).",
        {
            {"growth_rate_per_s", "Real part: growth (> 0) or decay rate.",
             number_schema(per_second),
             [](const core::Eigenmode& m) {
                 return quantity_json(m.eigenvalue.real(), per_second);
             }},
            {"frequency_Hz", "Im / 2 pi.", number_schema(hertz),
             [](const core::Eigenmode& m) { return quantity_json(m.frequency_Hz, hertz); }},
            {"damping_ratio", "-Re / |lambda|.", number_schema(one),
             [](const core::Eigenmode& m) { return quantity_json(m.damping_ratio, one); }},
        }};
    return table;
}

// rho's anatomy per span at its peak (docs/model.md §12.5).
const ResultTable<core::MarginFactors>& margin_factor_table() {
    static const ResultTable<core::MarginFactors> table{
        "TandemMarginFactors",
        "rho broken into its factors at the frequency of its peak, for one interstand span: the "
        "thickness it delivers enters its receiving stand (span + 1), whose bite turns it into a "
        "force and an entry-speed change and whose structure turns the force into a gap; the loop "
        "returns to the span through the tension and goes on downstream through the thickness "
        "(docs/model.md §12.5).",
        {
            {"span", "The interstand span, from 1 (between stands span and span + 1).",
             stand_number_schema(false),
             [](const core::MarginFactors& f) { return stand_number(f.span); }},
            {"worst_input_share",
             "The span's share |u_i|^2 / |u|^2 of the loop's worst input at the peak: where the "
             "gain is carried.",
             number_schema(one),
             [](const core::MarginFactors& f) { return quantity_json(f.worst_input_share, one); }},
            {"tension_loop_gain",
             "|M_ii|: the span's own loop, the receiving stand's entry thickness back to the "
             "exit thickness of the stand before the span through the tension path.",
             number_schema(one),
             [](const core::MarginFactors& f) { return quantity_json(f.tension_loop_gain, one); }},
            {"thickness_gain",
             "|M_{i+1,i}|: the receiving stand's entry thickness to its own exit thickness, the "
             "thickness path into the next span (null for the last span).",
             number_schema(one, true),
             [](const core::MarginFactors& f) {
                 return f.thickness_gain >= 0.0 ? quantity_json(f.thickness_gain, one)
                                                : json(nullptr);
             }},
            {"bite_force_gain_kN_per_mm",
             "dF/dy1 of the receiving stand's bite: roll force per entry thickness (the film and "
             "tensions held).",
             number_schema(kilonewton_per_millimetre),
             [](const core::MarginFactors& f) {
                 return quantity_json(f.force_per_entry_thickness, kilonewton_per_millimetre);
             }},
            {"bite_entry_speed_gain_per_s",
             "du1/dy1 of the receiving stand's bite: entry speed per entry thickness, (m/s)/m.",
             number_schema(per_second),
             [](const core::MarginFactors& f) {
                 return quantity_json(f.entry_speed_per_entry_thickness, per_second);
             }},
            {"compliance_um_per_kN",
             "|gap / force| of the receiving stand's six masses at the peak frequency (the "
             "strip's spring excluded: the bite is the strip).",
             number_schema(micrometre_per_kilonewton),
             [](const core::MarginFactors& f) {
                 return quantity_json(f.compliance, micrometre_per_kilonewton);
             }},
        }};
    return table;
}

// The frozen modes shown: the least damped first, at most this many (full detail).
constexpr std::size_t shown_frozen_modes = 12;

struct StabilityView {
    const TandemReport* report = nullptr;
};

const char* stability_status(const core::MillSpeedStability& s) {
    if (s.steady.status != core::MillSteadyStatus::ok) return "no_steady_state";
    if (s.frozen.status != core::DynamicsStatus::ok || !s.margin.ok || !s.nominal.ok)
        return "solver_failure";
    return "ok";
}

const ResultTable<StabilityView>& stability_table() {
    static const ResultTable<StabilityView> table{
        "TandemStability",
        "The mill's stability at its speed (docs/model.md §12.4-12.6).",
        {
            {"status",
             "ok; no_steady_state (see steady_state); solver_failure (a linearisation or the root "
             "count did not converge).",
             enum_schema({"ok", "no_steady_state", "solver_failure"}),
             [](const StabilityView& v) { return stability_status(v.report->at_speed); }},
            {"stable",
             "No root right of the imaginary axis with the nominal delays (the mill as it runs).",
             boolean_schema(true),
             [](const StabilityView& v) {
                 return v.report->at_speed.nominal.ok ? json(v.report->at_speed.nominal_stable)
                                                      : json(nullptr);
             }},
            {"frozen_stable", "A0 is stable: the tension path alone does not chatter.",
             boolean_schema(),
             [](const StabilityView& v) { return v.report->at_speed.frozen.stable; }},
            {"frozen_max_growth_rate_per_s", "The largest real part of A0's eigenvalues.",
             number_schema(per_second),
             [](const StabilityView& v) {
                 const auto& f = v.report->at_speed.frozen;
                 return f.status == core::DynamicsStatus::ok
                            ? quantity_json(f.max_real_part, per_second)
                            : json(nullptr);
             }},
            {"frozen_modes",
             "A0's oscillatory modes, the least damped first (12 at most; none in summary "
             "detail).",
             array_schema(ref_schema("TandemFrozenMode")),
             [](const StabilityView& v) {
                 json modes = json::array();
                 if (v.report->detail == Detail::summary) return modes;
                 std::vector<core::Eigenmode> sorted = v.report->at_speed.frozen.oscillatory;
                 std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
                     return a.eigenvalue.real() > b.eigenvalue.real();
                 });
                 for (std::size_t k = 0; k < sorted.size() && k < shown_frozen_modes; ++k)
                     modes.push_back(frozen_mode_table().write(sorted[k]));
                 return modes;
             }},
            {"regenerative_margin",
             "rho: the structured bound of the thickness loop over all delays (docs/model.md "
             "§12.5); rho < 1 with A0 stable: stable for every set of delays.",
             number_schema(one),
             [](const StabilityView& v) {
                 const auto& m = v.report->at_speed.margin;
                 return m.ok && m.frozen_stable ? quantity_json(m.margin, one) : json(nullptr);
             }},
            {"margin_frequency_Hz", "Where rho peaks.", number_schema(hertz),
             [](const StabilityView& v) {
                 const auto& m = v.report->at_speed.margin;
                 return m.ok && m.frozen_stable ? quantity_json(m.frequency_Hz, hertz)
                                                : json(nullptr);
             }},
            {"margin_validity",
             "Whether the frequency where rho peaks lies inside the model's range (the spring "
             "law and the quasi-static bite there; the factors are taken at it); null where rho "
             "is not a margin.",
             ref_schema("TandemValidity", true),
             [](const StabilityView& v) {
                 const auto& at = v.report->at_speed;
                 if (!at.margin.ok || !at.margin.frozen_stable || !(at.margin.frequency_Hz > 0.0))
                     return json(nullptr);
                 return validity_table().write(
                     core::crossing_validity(v.report->mill, at.steady, at.margin.frequency_Hz));
             }},
            {"margin_factors",
             "rho broken into its factors per interstand span at the frequency of its peak "
             "(empty where rho is not a margin: A0 unstable, or one stand).",
             array_schema(ref_schema("TandemMarginFactors")),
             [](const StabilityView& v) {
                 const auto& at = v.report->at_speed;
                 json rows = json::array();
                 if (!at.margin.ok || !at.margin.frozen_stable) return rows;
                 for (const core::MarginFactors& f : at.factors)
                     rows.push_back(margin_factor_table().write(f));
                 return rows;
             }},
            {"margin_exact",
             "rho >= 1 is also necessary for instability at some delays (one "
             "to three spans).",
             boolean_schema(),
             [](const StabilityView& v) { return v.report->at_speed.margin.exact; }},
            {"delay_independent_stable", "A0 stable and rho < 1.", boolean_schema(),
             [](const StabilityView& v) { return v.report->at_speed.delay_independent_stable; }},
            {"roots_right_of_axis",
             "The number of roots with the nominal delays right of the imaginary axis (the "
             "argument principle); null if the count failed.",
             integer_schema(true),
             [](const StabilityView& v) {
                 const auto& n = v.report->at_speed.nominal;
                 return n.ok ? json(n.count) : json(nullptr);
             }},
            {"roots_in_band",
             "Of those, the roots inside the model's band 0 < f < band_top_Hz (docs/model.md "
             "§12.7), counted as the nominal-delay critical speed counts them: 0 here means "
             "stable inside the model's range, whatever the roots above the band do; null if "
             "not counted.",
             integer_schema(true),
             [](const StabilityView& v) {
                 const int n = v.report->rightmost.band_count;
                 return n >= 0 ? json(n) : json(nullptr);
             }},
            {"band_top_Hz",
             "The top of the model's band at this speed: the largest frequency at which every "
             "span's spring law and every stand's quasi-static bite hold; 0: none does.",
             number_schema(hertz),
             [](const StabilityView& v) {
                 return v.report->rightmost.band_count >= 0
                            ? quantity_json(v.report->rightmost.band_top_Hz, hertz)
                            : json(nullptr);
             }},
            {"root_count_error",
             "The count's distance from an integer before rounding: its own accuracy.",
             number_schema(one),
             [](const StabilityView& v) {
                 const auto& n = v.report->at_speed.nominal;
                 return n.ok ? quantity_json(n.integer_error, one) : json(nullptr);
             }},
            {"delays_s", "The transport delays tau_i = L_i / u2_i of the interstand spans.",
             numbers_schema(second),
             [](const StabilityView& v) {
                 return quantities_json(v.report->at_speed.delay, second);
             }},
            {"rightmost_root",
             "The rightmost root with the nominal delays, by stand; null if none "
             "was found.",
             ref_schema("TandemRoot", true),
             [](const StabilityView& v) {
                 return v.report->rightmost.found ? root_table().write(v.report->rightmost)
                                                  : json(nullptr);
             }},
        }};
    return table;
}

// ---- the time domain ------------------------------------------------------------------------

// One stand's series in a run: the stand (0-based) and the run.
struct StandSeries {
    int index = 0;
    const core::MillTimeResult* run = nullptr;
};

// One column of a stand's series: `get` of each sample's stand, in `unit`.
Member<StandSeries> series_column(std::string_view name, std::string_view description, Unit unit,
                                  double (*get)(const core::MillStandSample&)) {
    return {name, description, numbers_schema(unit), [unit, get](const StandSeries& s) {
                json values = json::array();
                for (const core::MillTimeSample& sample : s.run->samples)
                    values.push_back(
                        quantity_json(get(sample.stands[static_cast<std::size_t>(s.index)]), unit));
                return values;
            }};
}

const ResultTable<StandSeries>& series_table() {
    static const ResultTable<StandSeries> table{
        "TandemStandSeries",
        "One stand's time series, columnar: element k of every array is at time_s[k].",
        {
            {"time_s", "Output times.", numbers_schema(second),
             [](const StandSeries& s) {
                 json values = json::array();
                 for (const core::MillTimeSample& sample : s.run->samples)
                     values.push_back(quantity_json(sample.t, second));
                 return values;
             }},
            series_column(
                "gap_change_um",
                "The work rolls' gap change q3 - q4 from the steady state (= y2 - y2_ref).",
                micrometre, [](const core::MillStandSample& x) { return x.gap; }),
            series_column("force_kN", "Roll force P.", kilonewton,
                          [](const core::MillStandSample& x) { return x.force; }),
            series_column("back_tension_MPa", "Back tension stress sigma_b.", megapascal,
                          [](const core::MillStandSample& x) { return x.back_tension; }),
            series_column("front_tension_MPa", "Front tension stress sigma_f.", megapascal,
                          [](const core::MillStandSample& x) { return x.front_tension; }),
            series_column("entry_thickness_mm",
                          "Entry thickness y1: the stand before's exit thickness a transport "
                          "time earlier.",
                          millimetre,
                          [](const core::MillStandSample& x) { return x.entry_thickness; }),
            series_column("exit_thickness_mm", "Exit thickness y2.", millimetre,
                          [](const core::MillStandSample& x) { return x.exit_thickness; }),
            series_column("exit_speed_m_per_s", "Exit strip speed u2.", metre_per_second,
                          [](const core::MillStandSample& x) { return x.exit_speed; }),
        }};
    return table;
}

const ResultTable<StandSeries>& stand_series_table() {
    static const ResultTable<StandSeries> table{
        "TandemStandTimeSeries",
        "A stand and its time series.",
        {
            {"stand", "The stand's number, 1 at the entry.", stand_number_schema(false),
             [](const StandSeries& s) { return stand_number(s.index); }},
            {"series", "Its series.", ref_schema("TandemStandSeries"),
             [](const StandSeries& s) { return series_table().write(s); }},
        }};
    return table;
}

// What the time series can be trusted for (time_table's range_note).
std::string time_series_range_note(const TandemReport& r) {
    if (!r.rightmost.found)
        return "no rightmost root at this speed to judge the range by: read the series with the "
               "stability answer";
    const core::MillCrossing& root = r.rightmost.described;
    const std::string at =
        concat("the rightmost root (", format_number(std::round(root.frequency_Hz * 10.0) / 10.0),
               " Hz, the mode the kick grows or decays with)");
    if (root.validity.valid()) return concat(at, " lies inside the model's range");
    std::string why;
    if (!root.validity.spring_law_valid)
        why = "the spring law's stiffness error exceeds 25 % there (use the segments span model)";
    if (!root.validity.quasi_static_bite_valid) {
        if (!why.empty()) why += "; ";
        why += "the bite transit exceeds 0.2 of the period there (the quasi-static bite)";
    }
    return concat(at, " lies outside the model's range: ", why,
                  "; the series shows the model, not the mill, at that frequency");
}

const ResultTable<TandemReport>& time_table() {
    static const ResultTable<TandemReport> table{
        "TandemTimeSeries",
        "The whole mill integrated in time from its steady state with a gap kick (docs/model.md "
        "§12.9): the thickness transport as a history of strip positions.",
        {
            {"status",
             "ok (the window was simulated); slack_span (a span's force reached zero: span names "
             "it); contact_lost or skidding (stand names it); solver_failure; step_budget; "
             "cancelled; invalid.",
             enum_schema({"ok", "slack_span", "contact_lost", "skidding", "solver_failure",
                          "step_budget", "cancelled", "invalid"}),
             [](const TandemReport& r) { return core::to_string(r.time->status); }},
            {"message", "What ended the run, for people; empty when ok.", string_schema(),
             [](const TandemReport& r) { return std::string(r.time->message); }},
            {"stand", "The stand that ended the run, or null.", stand_number_schema(true),
             [](const TandemReport& r) { return stand_number(r.time->stand); }},
            {"span",
             "The slack span, or null: 0 the entry span, i the span between stands i and i+1, N "
             "the exit span.",
             integer_schema(true),
             [](const TandemReport& r) {
                 return r.time->span < 0 ? json(nullptr) : json(r.time->span);
             }},
            {"end_time_s", "The last time reached (a limit's time when one ended the run).",
             number_schema(second),
             [](const TandemReport& r) { return quantity_json(r.time->end_time, second); }},
            {"kick_stand", "The stand kicked at t = 0.", stand_number_schema(true),
             [](const TandemReport& r) { return stand_number(r.kicked_stand); }},
            {"kick_um", "The gap kick.", number_schema(micrometre),
             [](const TandemReport& r) { return quantity_json(r.kick, micrometre); }},
            {"steps", "Integrator steps taken.", integer_schema(),
             [](const TandemReport& r) { return json(r.time->steps); }},
            {"in_model_range",
             "Whether the motion the series shows lies inside the model's range (docs/model.md "
             "§12.7): the time domain carries the same spring law and quasi-static bite as the "
             "roots, so it is judged at the rightmost root of the mill at its speed, the mode the "
             "kick grows or decays with; null when there is no such root.",
             boolean_schema(true),
             [](const TandemReport& r) {
                 return r.rightmost.found ? json(r.rightmost.described.validity.valid())
                                          : json(nullptr);
             }},
            {"range_note", "The range judgement in words, for people.", string_schema(),
             [](const TandemReport& r) { return time_series_range_note(r); }},
            {"stands", "Every stand's time series, from the entry.",
             array_schema(ref_schema("TandemStandTimeSeries")),
             [](const TandemReport& r) {
                 json stands = json::array();
                 for (int i = 0; i < r.mill.size(); ++i)
                     stands.push_back(stand_series_table().write({i, &*r.time}));
                 return stands;
             }},
        }};
    return table;
}

SteadyView steady_view(const TandemReport& report) {
    SteadyView view;
    view.steady = &report.at_speed.steady;
    const double f = report.rightmost.found ? report.rightmost.described.frequency_Hz : 0.0;
    for (std::size_t i = 0; i < report.at_speed.steady.stands.size(); ++i) {
        StandRow row;
        row.index = static_cast<int>(i);
        row.state = &report.at_speed.steady.stands[i];
        if (i + 1 < report.mill.thickness.size()) {
            row.entry_thickness = report.mill.thickness[i];
            row.exit_thickness = report.mill.thickness[i + 1];
        }
        if (f > 0.0 && row.state->exit_speed > 0.0) row.mark_spacing = row.state->exit_speed / f;
        view.rows.push_back(row);
    }
    return view;
}

const ResultTable<TandemReport>& result_table() {
    static const ResultTable<TandemReport> table{
        "TandemResult",
        "A tandem mill at its speed: steady state, stability and, when asked, its critical "
        "speeds (docs/model.md §12).",
        {
            {"steady_state", "The pass schedule at the mill speed.",
             ref_schema("TandemSteadyState"),
             [](const TandemReport& r) { return steady_table().write(steady_view(r)); }},
            {"stability", "Stability at the mill speed.", ref_schema("TandemStability"),
             [](const TandemReport& r) { return stability_table().write({&r}); }},
            {"critical_speeds", "The three critical speeds (options.critical_speed).",
             ref_schema("TandemCriticalSpeeds"),
             [](const TandemReport& r) {
                 return r.critical ? critical_table().write(*r.critical) : absent();
             },
             true},
            {"time_series", "The mill in time after a gap kick (options.time_series).",
             ref_schema("TandemTimeSeries"),
             [](const TandemReport& r) { return r.time ? time_table().write(r) : absent(); }, true},
        }};
    return table;
}

json crossing_rows(const json& result) {
    json rows = json::array();
    const auto critical = result.find("critical_speeds");
    if (critical == result.end()) return rows;
    for (const char* kind : {"frozen", "delay_independent", "nominal_delay"}) {
        if (critical->contains(kind)) rows.push_back(critical->at(kind));
    }
    return rows;
}

const std::array<CsvTable, 4> csv_tables{{
    {"stands",
     "The steady state, one row per stand.",
     "",
     {},
     "/steady_state/stands",
     [](const json&) { return stand_table().scalar_names(); }},
    {"crossings",
     "The three critical speeds, one row each (critical_speed true).",
     "",
     {},
     "",
     [](const json&) { return crossing_table().scalar_names(); },
     &crossing_rows},
    {"frozen_modes",
     "A0's least damped oscillatory modes.",
     "",
     {},
     "/stability/frozen_modes",
     [](const json&) { return frozen_mode_table().scalar_names(); }},
    {"time_series",
     "Each stand's time series after the kick (time_series true), stand by stand.",
     "/time_series/stands",
     {{"stand", "stand"}},
     "/series",
     [](const json&) { return series_table().names(); }},
}};

}  // namespace

nlohmann::json tandem_result_json(const TandemReport& report) {
    return result_table().write(report);
}

std::vector<ResultSchema> tandem_result_schemas() {
    return {result_schema(stand_table()),         result_schema(steady_table()),
            result_schema(validity_table()),      result_schema(root_table()),
            result_schema(crossing_table()),      result_schema(critical_table()),
            result_schema(frozen_mode_table()),   result_schema(stability_table()),
            result_schema(margin_factor_table()), result_schema(series_table()),
            result_schema(stand_series_table()),  result_schema(time_table()),
            result_schema(result_table())};
}

std::span<const CsvTable> tandem_csv_tables() { return csv_tables; }

nlohmann::json tandem_critical_speeds_json(const core::MillCriticalSpeeds& speeds) {
    return critical_table().write(speeds);
}

nlohmann::json stand_number(int index) {
    return index < 0 ? nlohmann::json(nullptr) : nlohmann::json(index + 1);
}

nlohmann::json stand_number_schema(bool nullable) {
    nlohmann::json schema = integer_schema(nullable);
    schema["minimum"] = 1;
    schema["maximum"] = core::max_mill_stands;
    return schema;
}

}  // namespace rollgap::api
