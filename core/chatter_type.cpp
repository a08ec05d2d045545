#include "core/chatter_type.h"

#include <algorithm>
#include <cmath>

namespace rollgap::core {

const char* to_string(ChatterType type) {
    switch (type) {
        case ChatterType::third_octave: return "third_octave";
        case ChatterType::fifth_octave: return "fifth_octave";
        case ChatterType::other: return "other";
    }
    return "other";
}

ChatterType chatter_band(double frequency_Hz, const ChatterBands& bands) {
    if (frequency_Hz >= bands.third_octave_low && frequency_Hz <= bands.third_octave_high) {
        return ChatterType::third_octave;
    }
    if (frequency_Hz >= bands.fifth_octave_low && frequency_Hz <= bands.fifth_octave_high) {
        return ChatterType::fifth_octave;
    }
    return ChatterType::other;
}

ChatterShape chatter_shape(const Vector6c& q) {
    ChatterShape out;
    const double largest = q.cwiseAbs().maxCoeff();
    if (!(largest > 0.0) || !std::isfinite(largest)) return out;
    const std::complex<double> upper_work = q(2), lower_work = q(3);
    const double work_sum = std::abs(upper_work) + std::abs(lower_work);
    out.gap_opening = work_sum > 0.0 ? std::abs(upper_work - lower_work) / work_sum : 0.0;
    out.work_roll_motion = std::max(std::abs(upper_work), std::abs(lower_work)) / largest;
    const bool upper = std::abs(upper_work) >= std::abs(lower_work);
    const std::complex<double> work = upper ? upper_work : lower_work;
    const std::complex<double> backup = upper ? q(1) : q(4);
    const double work2 = std::norm(work);
    out.backup_follow = work2 > 0.0 ? (backup * std::conj(work)).real() / work2 : 0.0;
    return out;
}

ChatterClassification classify_chatter(const Vector6c& displacement, double frequency_Hz,
                                       const ChatterBands& bands) {
    ChatterClassification out;
    out.band = chatter_band(frequency_Hz, bands);
    out.shape = chatter_shape(displacement);
    const ChatterShape& s = out.shape;
    if (s.gap_opening < gap_opening_min || s.work_roll_motion < work_roll_motion_min) {
        out.type = ChatterType::other;
    } else if (s.backup_follow < backup_follow_min) {
        out.type = ChatterType::fifth_octave;
    } else {
        out.type = ChatterType::third_octave;
    }
    return out;
}

}  // namespace rollgap::core
