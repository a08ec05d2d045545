#include "core/inlet_film.h"

#include <cmath>

namespace rollgap::core {

double inlet_pressure_factor(double pressure_viscosity, double flow_stress, double back_tension) {
    return -std::expm1(-pressure_viscosity * (flow_stress - back_tension));
}

namespace {

// S(q) = artanh(sqrt q) / sqrt q for 0 < q < 1, atan(sqrt(-q)) / sqrt(-q) for q < 0.
// one_minus_q is passed separately because near q = 1 (thin films) it is known exactly.
double inverse_tanh_ratio(double q, double one_minus_q) {
    if (q > 0.0) {
        const double r = std::sqrt(q);
        return (std::log1p(r) - 0.5 * std::log(one_minus_q)) / r;
    }
    const double r = std::sqrt(-q);
    return std::atan(r) / r;
}

}  // namespace

double wilson_walowit_film(double viscosity, double pressure_viscosity, double mean_inlet_speed,
                           double inlet_angle, double flow_stress, double back_tension) {
    return wilson_walowit_film_of(viscosity, pressure_viscosity, mean_inlet_speed, inlet_angle,
                                  flow_stress, back_tension);
}

// With q = e / (a theta^2) = 1 - 2 h0 / (a theta^2), the model document's closed form becomes
//   I2 = [(3 - q) S(q) - 3] / (q^2 theta^3),
// which is the same expression for e > 0 (log) and e < 0 (atan). Its two terms cancel as
// q -> 0; there the series I2 = theta^-3 sum_j 4 (j + 1) q^j / ((2j + 3)(2j + 5)) is used
// (at q = 0 the inlet is (x + a theta)^2 / (2a) and I2 = 4 / (15 theta^3) exactly).
double inlet_integral_I2(double roll_radius, double inlet_angle, double inlet_film) {
    const double theta3 = inlet_angle * inlet_angle * inlet_angle;
    const double one_minus_q = 2.0 * inlet_film / (roll_radius * inlet_angle * inlet_angle);
    const double q = 1.0 - one_minus_q;
    if (std::abs(q) < 0.05) {
        double sum = 0.0, power = 1.0;
        for (int j = 0; j < 40; ++j) {
            sum += 4.0 * (j + 1) * power / ((2.0 * j + 3.0) * (2.0 * j + 5.0));
            power *= q;
        }
        return sum / theta3;
    }
    return ((3.0 - q) * inverse_tanh_ratio(q, one_minus_q) - 3.0) / (q * q * theta3);
}

double inlet_film_rate(InletFilmModel model, const InletFilmInputs& in) {
    const double theta = in.inlet_angle;
    const double supply = theta * in.mean_inlet_speed;
    const double relaxation =
        theta * theta * in.inlet_film *
        reduced_pressure_over_gamma(in.pressure_viscosity, in.flow_stress - in.back_tension) /
        (6.0 * in.viscosity);
    switch (model) {
        case InletFilmModel::eulerian: return supply - 0.5 * in.gap_rate - relaxation;
        case InletFilmModel::paper: break;
    }
    const double I2 = inlet_integral_I2(in.roll_radius, theta, in.inlet_film);
    return supply - theta * theta * in.inlet_film * in.inlet_angle_rate * I2 - relaxation;
}

}  // namespace rollgap::core
