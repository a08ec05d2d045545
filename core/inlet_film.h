#pragma once
// The inlet film of docs/model.md §2: Reynolds + Barus in the inlet zone, the unsteady film
// equation (11) and its steady state, the Wilson-Walowit film.

#include <cmath>

#include "core/scenario.h"

namespace rollgap::core {

// The pressure the inlet must build to reach the bite, 1 - exp(-gamma (sigma - s_b)).
double inlet_pressure_factor(double pressure_viscosity, double flow_stress, double back_tension);

// Steady (Wilson-Walowit) film h00 = 6 eta0 gamma u1bar / (theta (1 - exp(-gamma (sigma - s_b)))),
// u1bar = (u1 + v) / 2.
double wilson_walowit_film(double viscosity, double pressure_viscosity, double mean_inlet_speed,
                           double inlet_angle, double flow_stress, double back_tension);

// The same film for a scalar that may carry derivatives (core/dual.h): the bite sensitivities
// (docs/model.md §6.1) differentiate it through the trial entry speed, the inlet angle and s_b.
// (1 - exp(-gamma p)) / gamma tends to p as gamma -> 0 (isoviscous inlet).
template <class T>
T reduced_pressure_over_gamma(double pressure_viscosity, const T& pressure) {
    using std::abs;
    using std::expm1;
    const T gp = pressure_viscosity * pressure;
    if (abs(gp) < 1e-8) return pressure * (1.0 - 0.5 * gp);
    return -expm1(-gp) / pressure_viscosity;
}

template <class T>
T wilson_walowit_film_of(double viscosity, double pressure_viscosity, const T& mean_inlet_speed,
                         const T& inlet_angle, double flow_stress, const T& back_tension) {
    return 6.0 * viscosity * mean_inlet_speed /
           (inlet_angle *
            reduced_pressure_over_gamma(pressure_viscosity, T(flow_stress - back_tension)));
}

// I2 = int_0^inf x^2 / h1(x)^3 dx on the circular inlet h1 = h0 + theta x + x^2 / (2a),
// in closed form (docs/model.md §2); dimensionless (m^2 m / m^3).
double inlet_integral_I2(double roll_radius, double inlet_angle, double inlet_film);

struct InletFilmInputs {
    double inlet_film;          // h0, m
    double inlet_angle;         // theta
    double inlet_angle_rate;    // d theta / dt, 1/s
    double gap_rate;            // d yc / dt, m/s (opening positive)
    double mean_inlet_speed;    // u1bar, m/s
    double roll_radius;         // a, m
    double viscosity;           // eta0
    double pressure_viscosity;  // gamma
    double flow_stress;         // sigma
    double back_tension;        // s_b
};

// dh0/dt of the selected model: `paper` is eq. (11) with C_R = -I2,
//   dh0/dt = theta u1bar - theta^2 h0 thetadot I2 - theta^2 h0 (1 - e^{-gamma(sigma - s_b)}) / (6
//   gamma eta0);
// `eulerian` replaces the thetadot term by the uniform squeeze -dyc/dt / 2.
double inlet_film_rate(InletFilmModel model, const InletFilmInputs& in);

}  // namespace rollgap::core
