#pragma once
// The mill's three critical speeds (docs/model.md §12.7): `frozen` (A0 turns unstable: the
// tension path alone), `delay_independent` (A0 unstable or rho >= 1: the first speed at which
// some set of transport delays destabilises the mill, the robust limit) and `nominal_delay` (the
// first root with the actual delays crossing the axis), each with its frequency, the stand that
// moves, the band, and the validity of the spring law and the quasi-static bite there; the
// headline is the lowest whose crossing lies inside the model's range.

#include <complex>
#include <vector>

#include "core/chatter_type.h"
#include "core/control.h"
#include "core/mill/mill.h"
#include "core/mill/mill_stability.h"
#include "core/stability.h"

namespace rollgap::core {

// The mill linearised at its own speed (docs/model.md §12.4-12.5): its schedule, A0 and the
// transport transfer M(s); ok false without a steady state or a linearisation. gains: each
// stand's J_b scaled by gains[i] (empty: all 1).
struct MillTransfer {
    bool ok = false;
    MillSteadyState steady;
    TransportTransfer transfer;
};
MillTransfer mill_transfer(const Mill& mill, std::vector<double> gains = {});

// Per-stand shares of a mill state vector's motion, mass-weighted over the six masses of each
// stand (sum_k m_k |q_k|^2, normalised to sum 1): the stand that moves is the largest.
std::vector<double> mill_participation(const Mill& mill, const Eigen::VectorXcd& z);

// Whether a crossing at `frequency_Hz` lies inside the model's range (docs/model.md §12.7):
// per span omega L / c and the spring law's stiffness error 1 - x / tan x (x = omega L / c; the
// law is outside its range above 0.25), per stand the bite transit time x_w / u1 over the period
// (the quasi-static bite is outside its range above 0.2).
struct CrossingValidity {
    std::vector<double> span_wave_number;    // omega L_i / c, interstand spans
    std::vector<double> spring_law_error;    // 1 - x / tan x
    std::vector<double> bite_transit_ratio;  // (x_w / u1) f per stand
    bool spring_law_valid = true;
    bool quasi_static_bite_valid = true;
    bool valid() const { return spring_law_valid && quasi_static_bite_valid; }
};
CrossingValidity crossing_validity(const Mill& mill, const MillSteadyState& steady,
                                   double frequency_Hz);

enum class MillCrossingKind { frozen, delay_independent, nominal_delay };
const char* to_string(MillCrossingKind);

struct MillCrossing {
    MillCrossingKind kind = MillCrossingKind::frozen;
    CriticalSpeedStatus status = CriticalSpeedStatus::no_steady_state;
    double speed = 0.0;         // m/s, when found
    double frequency_Hz = 0.0;  // of the crossing root (delay_independent: where rho peaks)
    int moving_stand = -1;      // 0-based: the largest participation
    std::vector<double> participation;
    // d(growth)/d kappa_i with J_b,i -> (1 + kappa_i) J_b,i, per stand: the crossing root's
    // growth rate (1/s; delay_independent: rho itself, per unit kappa). The feeding stand, whose
    // bite process feeds the vibration (where a change of its bite helps most), is the largest.
    std::vector<double> feeding_sensitivity;
    int feeding_stand = -1;
    ChatterType band = ChatterType::other;
    // the chatter type by shape (docs/model.md "Chatter type"): the moving stand's six masses in
    // the crossing's motion, as a single stand's mode is classified (its band beside it)
    ChatterClassification chatter;
    CrossingValidity validity;
    // nominal_delay: the lobe period Delta V ~ V / (f tau_max) beside it, m/s
    double lobe_period = 0.0;
};

struct MillCriticalSpeeds {
    // nominal_delay: the first speed where a root inside the model's band crosses (0 < Im s <
    // 2 pi f_valid of that speed, band_root_count); first_any: the first where any root does,
    // valid or not (not a candidate for the headline; never dropped)
    MillCrossing frozen, delay_independent, nominal_delay, first_any;
    // the lowest found crossing inside the model's range; -1 if none is
    int headline = -1;  // 0 frozen, 1 delay_independent, 2 nominal_delay
    // found crossings below the headline (or all, when none is valid) that lie outside the range
    std::vector<MillCrossingKind> outside_range_below;
};

// A root of the mill at its own speed, described as a crossing is (docs/model.md §12.7): the
// rightmost root with the nominal delays of `at` (mill_stability_at of `mill`), its frequency,
// participation and moving stand, the bite-gain sensitivity of its growth rate and the feeding
// stand, band and validity. `found` false: `at` has no rightmost root.
struct MillRootDescription {
    bool found = false;
    bool verified = false;   // no root right of it (the count)
    std::complex<double> s;  // 1/s
    MillCrossing described;  // kind nominal_delay, speed the mill's; status found when found
    // The roots right of the axis inside the model's band 0 < f < band_top_Hz (band_root_count,
    // upper half plane), -1 when not counted (no steady state, or the count did not close);
    // band_top_Hz 0: the band is empty at this speed.
    int band_count = -1;
    double band_top_Hz = 0.0;
    double band_count_error = 0.0;  // the count's distance from an integer
};
MillRootDescription describe_rightmost_root(const Mill& mill, const MillSpeedStability& at);

// The band's screen (docs/model.md §12.7): the first speed from `start` up where the structured
// gain over the model's band 0.01 Hz .. f_valid on the axis reaches 0.9 (or A0 turns unstable),
// by the single stand's search (a scan of options.speed_step from start, bisected); the gain over
// the band is the regenerative margin restricted to it (200 frequencies plus A0's poles, peaks
// refined). A root on the axis at i omega needs rho(M E) = 1 there, which the gain bounds from
// above for every set of delays: below this speed no root crosses the axis inside the band. 0.9,
// not 1, leaves room for a peak between the grid's frequencies. options.speed_max when the gain
// stays below it; `start` when it is above at start.
double mill_band_screen_speed(const Mill& mill, double start, CriticalSpeedOptions options,
                              const Control& control = {});

// frozen: the single stand's search on A0 (§7.3); delay_independent: the same search on
// g = rho - 1 while A0 is stable (+1 where it is not; rho grows without bound as A0 nears
// instability, so g crosses zero first); nominal_delay: from the delay-independent speed (below
// it every set of delays is stable) upwards in steps of half a lobe period at the model's top
// valid frequency f_valid (Delta V = V / (f_valid tau_max), recomputed each block; from the band's
// screen, mill_band_screen_speed, and again from the delay-independent speed if a root is in the
// band already there) until a root inside the band 0 < Im s < 2 pi f_valid lies right of the
// axis (band_root_count), at most 400 steps, then bisection on that count to the search's
// tolerance; first_any: the same search on "any root right of the axis"
// (nominal_delay_root_count) in steps of half a lobe period at the delay-independent frequency
// (tau_max taken at each block's first speed). The frozen and delay-independent searches run side
// by side, then first_any beside the band's screen and scan (each on the control's threads).
MillCriticalSpeeds mill_critical_speeds(const Mill& mill, const CriticalSpeedOptions& options = {},
                                        const Control& control = {});

}  // namespace rollgap::core
