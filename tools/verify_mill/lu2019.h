#pragma once
// The published five-stand schedule of Lu et al., Shock and Vibration 2019, art. 4358631,
// Table 1 (as quoted by the mill specification): the verification
// report's comparison (tools/verify_mill) and the data's own mass-flow test
// (tests/core/test_mill.cpp) read it from here. Units: mm, MPa, m/s, kN.

namespace rollgap::tools::lu2019 {

inline constexpr int stands = 5;
inline constexpr double thickness_mm[stands + 1] = {2.000, 1.269, 0.762, 0.460, 0.300, 0.200};
inline constexpr double entry_tension_MPa = 55.0;
inline constexpr double interstand_tension_MPa[stands - 1] = {140.554, 165.252, 188.160, 205.575};
inline constexpr double exit_tension_MPa = 68.0;
inline constexpr double coulomb_coefficient[stands] = {0.065, 0.060, 0.040, 0.030, 0.020};
inline constexpr double roll_speed[stands] = {3.381, 5.652, 9.425, 14.441, 22.121};
inline constexpr double entry_speed[stands] = {2.250, 3.546, 5.903, 9.774, 14.977};
inline constexpr double force_kN[stands] = {7838.9, 8455.2, 7781.6, 7501.0, 7722.7};

}  // namespace rollgap::tools::lu2019
