#pragma once
// Which kind of chatter a mode of the six-mass stack is (docs/model.md, "Chatter type"): decided
// from the mode shape, which masses move against which, with the frequency band beside it as a
// check. Masses as in core/scenario.h: m1 upper crosshead, m2 upper back-up roll, m3 upper work
// roll, m4 lower work roll, m5 lower back-up roll, m6 lower crosshead.

#include <complex>

#include <Eigen/Dense>

namespace rollgap::core {

using Vector6c = Eigen::Matrix<std::complex<double>, 6, 1>;

// third_octave: the roll packages move as units against each other, opening and closing the gap
// (the gap / tension mode of the stand, typically 100-300 Hz). fifth_octave: the work rolls
// vibrate against their back-up rolls across the strip (typically 500-700 Hz). other: the mode
// hardly changes the gap, so the bite neither sees nor drives it.
enum class ChatterType { third_octave, fifth_octave, other };
const char* to_string(ChatterType);

// The literature's typical frequency bands, closed intervals in Hz.
struct ChatterBands {
    double third_octave_low = 100.0, third_octave_high = 300.0;
    double fifth_octave_low = 500.0, fifth_octave_high = 700.0;
};

// The type the frequency alone suggests.
ChatterType chatter_band(double frequency_Hz, const ChatterBands& bands = {});

// The measures the shape criterion rests on, each dimensionless.
struct ChatterShape {
    // |q3 - q4| / (|q3| + |q4|): 1 when the work rolls move exactly against each other (the
    // gap breathes), 0 when they move together (the gap keeps its size)
    double gap_opening = 0.0;
    // max(|q3|, |q4|) / max |q|: how much of the mode the work rolls carry
    double work_roll_motion = 0.0;
    // Re(q_b conj(q_w)) / |q_w|^2 on the side whose work roll moves more (w, b: its work and
    // back-up roll): how far the back-up roll follows its work roll, in units of the work
    // roll's motion; 1 when they move as one, 0 when the back-up roll stands still, negative
    // when it moves against the work roll
    double backup_follow = 0.0;
};

struct ChatterClassification {
    ChatterType type = ChatterType::other;  // from the shape: this is the answer
    ChatterType band = ChatterType::other;  // from the frequency, reported beside it
    ChatterShape shape;
    bool agrees() const { return type == band; }
};

// Thresholds of the shape criterion.
inline constexpr double gap_opening_min =
    0.5;  // the work rolls move more against than with each other
inline constexpr double work_roll_motion_min = 0.1;  // the work rolls take part in the mode
inline constexpr double backup_follow_min = 0.5;     // the back-up roll carries its work roll along

ChatterShape chatter_shape(const Vector6c& displacement);

// displacement: q of m1..m6 with phase (any common complex scale); all zero (a non-oscillatory
// or shapeless mode) is `other`.
ChatterClassification classify_chatter(const Vector6c& displacement, double frequency_Hz,
                                       const ChatterBands& bands = {});

}  // namespace rollgap::core
