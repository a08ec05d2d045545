#pragma once
// The mill with its nominal transport delays (docs/model.md §12.6): the roots of
//   chi(s) = det(sI - A0) det(I - M(s) E(s)),   E(s) = diag(exp(-s tau_i)),
// counted to the right of Re s = alpha by the argument principle on F = det(I - M E) (exact: no
// rational approximation of the delays), and found one by one by Newton's method on F.

#include <complex>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "core/mill/mill_regenerative.h"

namespace rollgap::core {

// F(s) = det(I - M(s) E(s)).
std::complex<double> delay_characteristic(const TransportTransfer& transfer,
                                          std::complex<double> s);

struct DelayRootCount {
    bool ok = false;
    const char* message = "";
    int count = 0;               // roots of chi with Re s > alpha
    double alpha = 0.0;          // the line used (moved off A0's poles when one sits on it)
    int frozen_right = 0;        // eigenvalues of A0 with Re > alpha
    double winding = 0.0;        // -(change of arg F along the line from 0 to +i inf) / pi
    double integer_error = 0.0;  // |frozen_right + winding - count|: the count's own accuracy
    int evaluations = 0;         // F evaluated
    int sampled = 0;             // grid points where M and the structured gain were computed
    // Where |F| dips along the followed parts of the line (local minima, the 16 smallest): the
    // roots nearest the line lie beneath them, Newton's starts for the rightmost root.
    std::vector<std::complex<double>> dips;
};

// The argument principle on the line s = alpha + i omega, omega from 0 to infinity (F is real on
// the real axis, so the other half mirrors it): where the structured gain sigma(D M D^-1)
// max_i exp(-alpha tau_i) is below 1/2 at both ends of a grid interval, or below 0.9 at its ends
// and middle, every eigenvalue of M E stays inside the unit disc and arg F is the sum of the
// principal arguments of I - M E's eigenvalues (docs/model.md §12.6), so no delay phase need be
// followed there; elsewhere arg F is followed with steps of at most 1/tau_max (no delay phase
// turns by more than a radian) and a quarter of the distance to A0's nearest pole, halved until
// each increment is under pi/4, M interpolated along the walk where it is smooth enough.
DelayRootCount nominal_delay_root_count(const TransportTransfer& transfer, double alpha = 0.0);

// The stretches of the line Re s = alpha (omega ranges, rad/s) where the structured gain reaches
// `threshold` (< 0.9) on the count's grid: the intervals whose ends are not both below 1/2, nor
// both ends and middle below the threshold, merged. Outside them the count follows no winding.
struct LoudStretches {
    bool ok = false;
    double alpha = 0.0;
    std::vector<std::pair<double, double>> omega;
};
LoudStretches loud_stretches(const TransportTransfer& transfer, double alpha, double threshold);
LoudStretches loud_union(const LoudStretches& x, const LoudStretches& y);

// The same count taking the line's quiet parts from `loud` (found at nearby speeds of the same
// mill: docs/model.md §12.7, first_any): only this speed's grid points inside the stretches (and
// their neighbours, omega = 0 and the last) are sampled, the gaps between them taken as quiet,
// their ends checked (a gain of 0.9 at one: the whole line is counted instead).
DelayRootCount nominal_delay_root_count(const TransportTransfer& transfer, double alpha,
                                        const LoudStretches& loud);

struct DelayRoot {
    bool converged = false;
    std::complex<double> s;  // 1/s
    double residual = 0.0;   // |F(s)|
    int iterations = 0;
};

struct RightmostDelayRoot {
    bool found = false;
    bool verified = false;  // the count right of it is zero
    DelayRoot root;
    int starts = 0;  // Newton runs
    int counts = 0;  // counts taken to verify
};

// The rightmost root: Newton's from the count's dips and from A0's oscillatory poles with
// frequencies in (0, 2000] Hz, the largest real part among the converged (|F| < 1e-8); then
// the count just right of it (Re s > Re r + max(1e-3, 1e-9 |r|)) says whether any root lies
// further right, and if one does, Newton again from that count's dips, which lie beside it; up
// to eight rounds.
RightmostDelayRoot rightmost_delay_root(const TransportTransfer& transfer,
                                        const DelayRootCount& count);

// The roots of chi inside the band alpha < Re s, 0 < Im s < omega_max (docs/model.md §12.7: the
// model's valid frequencies; the conjugates in -omega_max < Im s < 0 are implied, the real roots
// excluded), counted as nominal_delay_root_count counts them (zeros of det(sI - A0) F, i.e.
// frozen_inside + winding) by the argument principle on the rectangle [alpha, right] x
// [epsilon, omega_max], traversed counter-clockwise:
//   bottom  Im s = epsilon (1e-6 max(1, omega_max) / 2pi, below every oscillatory root the band
//           means; real roots and A0's real poles lie under it, outside),
//   right   Re s = right, where the structured gain sigma(D M D^-1) max_i exp(-right tau_i) < 1/2
//           on the whole edge (no winding there, and none further right: right is doubled from
//           A0's rightmost pole + 1 until it holds),
//   top     Im s = omega_max, from right back to alpha,
//   left    Re s = alpha, from omega_max down to epsilon: the line of nominal_delay_root_count.
// Along every edge arg F is followed as on the line: where the gain at both ends of a grid
// interval is below 1/2 (or 0.9 at its ends and middle) by the eigenvalues' principal arguments,
// elsewhere in steps of at most 1/tau_max and a quarter of the distance to A0's nearest pole,
// halved until each increment is under pi/4. An edge on one of A0's poles is moved off it by a hair
// (alpha and right rightward, epsilon and omega_max upward).
struct BandRootCount {
    bool ok = false;
    const char* message = "";
    int count = 0;               // roots of chi in the band (upper half), Re s > alpha
    double alpha = 0.0;          // the left edge used
    double omega_max = 0.0;      // the top edge used, 1/s
    double epsilon = 0.0;        // the bottom edge, 1/s
    double right = 0.0;          // the right edge, 1/s
    int frozen_inside = 0;       // eigenvalues of A0 inside the rectangle
    double winding = 0.0;        // (change of arg F around the rectangle) / 2pi
    double integer_error = 0.0;  // |frozen_inside + winding - count|
    int evaluations = 0;         // F (or the loop's eigenvalues) evaluated
    // where |F| dips along the left edge (the 16 smallest) and along the top and bottom edges
    // (the 8 smallest): Newton's starts for the band's rightmost root
    std::vector<std::complex<double>> dips;
};

BandRootCount band_root_count(const TransportTransfer& transfer, double omega_max,
                              double alpha = 0.0);

// The rightmost root inside the band 0 < Im s < omega_max (whatever its real part): Newton's
// from the band count's dips (at alpha = 0) and from A0's poles in the band, the largest real
// part among the converged (|F| < 1e-8) in the band; verified when the band count just right of
// it (Re s > Re r + max(1e-3, 1e-9 |r|)) is zero, else Newton again from that count's dips; up
// to eight rounds. found is false when no start converges inside the band.
RightmostDelayRoot band_rightmost_root(const TransportTransfer& transfer,
                                       const BandRootCount& count);

// Newton's method on F from `start` (the derivative by central differences, F analytic), to
// |step| <= 1e-12 |s|.
DelayRoot delay_root(const TransportTransfer& transfer, std::complex<double> start);

}  // namespace rollgap::core
