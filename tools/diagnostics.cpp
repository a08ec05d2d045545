#include "tools/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "core/coupled_model.h"
#include "core/stand_structure.h"
#include "core/roll_bite.h"
#include "core/stability.h"

namespace rollgap::tools {

using core::balanced_eigenvalues;

namespace {

// The oscillatory eigenvalue nearest in frequency to `frequency_Hz`, or the one with the
// largest real part when frequency_Hz <= 0.
std::complex<double> pick_mode(const Eigen::VectorXcd& values, double frequency_Hz) {
    std::complex<double> best(std::nan(""), std::nan(""));
    double best_score = INFINITY;
    for (Eigen::Index i = 0; i < values.size(); ++i) {
        const std::complex<double> lambda = values(i);
        if (!(lambda.imag() > 0.0)) continue;
        const double score = frequency_Hz > 0.0
                                 ? std::abs(lambda.imag() / (2.0 * std::numbers::pi) - frequency_Hz)
                                 : -lambda.real();
        if (score < best_score) {
            best_score = score;
            best = lambda;
        }
    }
    return best;
}

Eigen::MatrixXd without_state(const Eigen::MatrixXd& J, int index) {
    const int n = static_cast<int>(J.rows());
    std::vector<int> keep;
    for (int i = 0; i < n; ++i) {
        if (i != index) keep.push_back(i);
    }
    Eigen::MatrixXd out(n - 1, n - 1);
    for (int r = 0; r < n - 1; ++r) {
        for (int c = 0; c < n - 1; ++c)
            out(r, c) = J(keep[static_cast<std::size_t>(r)], keep[static_cast<std::size_t>(c)]);
    }
    return out;
}

}  // namespace

ModeDiagnostics diagnose(const core::Scenario& s, double mode_frequency_Hz) {
    using namespace rollgap::core;
    ModeDiagnostics d;
    d.speed = s.rolls.speed;

    const BiteResult bite = solve_roll_bite(s, steady_bite_state(s));
    if (bite.status != BiteStatus::ok) {
        d.message = "no steady state";
        return d;
    }
    d.mean_friction = bite.mean_friction_coefficient;
    d.inlet_film = bite.inlet_film;
    d.inlet_angle = bite.inlet_angle;
    d.contact_length = bite.contact_length;
    d.entry_speed = bite.entry_speed;
    d.force = bite.force;
    d.film_ratio_min = INFINITY;
    d.film_ratio_max = -INFINITY;
    d.contact_ratio_max = 0.0;
    for (const BitePoint& p : bite.distribution) {
        d.film_ratio_min = std::min(d.film_ratio_min, p.film_ratio);
        d.film_ratio_max = std::max(d.film_ratio_max, p.film_ratio);
        d.contact_ratio_max = std::max(d.contact_ratio_max, p.contact_ratio);
    }

    const Scenario dynamics = dynamics_scenario(s);
    const ReferenceState ref = reference_state(dynamics, true);
    if (ref.status != BiteStatus::ok) {
        d.message = "no reference state for the dynamics";
        return d;
    }
    d.strip_stiffness = ref.strip_stiffness;
    const CoupledModel model(dynamics, ref);
    const Linearisation lin = linearise(model, model.equilibrium());
    if (lin.status != DynamicsStatus::ok) {
        d.message = "the linearisation failed";
        return d;
    }
    const Eigen::MatrixXd& J = lin.jacobian;
    const StructureMatrices& mill = model.structure();
    const int film = CoupledModel::film_index;
    const int back = model.back_tension_index();

    // Row 8 is q3'' = (dP - C q' - K_s q)_3 / m3 (b = e3 - e4, M diagonal).
    const double m3 = mill.mass(2, 2);
    d.dP_dgap = m3 * J(8, 2) + mill.structural_stiffness(2, 2);
    d.dP_dgap_rate = m3 * J(8, 8) + mill.damping(2, 2);
    d.dP_dfilm = m3 * J(8, film);
    double Fg = J(film, 2), Fgd = J(film, 8), Fh = J(film, film), Fs = 0.0;
    double Tg = 0.0, Tgd = 0.0, Th = 0.0, Ts = 0.0, Ps = 0.0;
    if (back >= 0) {
        Ps = m3 * J(8, back);
        d.dP_dback = Ps;
        Fs = J(film, back);
        Tg = J(back, 2);
        Tgd = J(back, 8);
        Th = J(back, film);
        Ts = J(back, back);
        d.tension_pole = Ts;
        d.du1_dgap = Tg * s.tensions.back.span_length / s.strip.youngs_modulus;
    }

    const std::complex<double> lambda = pick_mode(balanced_eigenvalues(J), mode_frequency_Hz);
    if (!std::isfinite(lambda.real())) {
        d.message = "no oscillatory eigenvalue";
        return d;
    }
    d.frequency_Hz = lambda.imag() / (2.0 * std::numbers::pi);
    d.growth_rate = lambda.real();
    if (back >= 0)
        d.growth_constant_tension =
            pick_mode(balanced_eigenvalues(without_state(J, back)), d.frequency_Hz).real();
    d.growth_frozen_film =
        pick_mode(balanced_eigenvalues(without_state(J, film)), d.frequency_Hz).real();

    // The force response to a harmonic gap motion g e^{i w t}: the film and tension states obey
    //   (iw - A2) (h0, s_b) = (F_g + iw F_gd, T_g + iw T_gd) g.
    const double w = lambda.imag();
    const std::complex<double> iw(0.0, w);
    Eigen::Matrix2cd A;
    A << iw - Fh, -Fs, -Th, iw - Ts;
    Eigen::Vector2cd drive(Fg + iw * Fgd, Tg + iw * Tgd);
    if (back < 0) {
        A(1, 1) = 1.0;
        A(1, 0) = 0.0;
        A(0, 1) = 0.0;
        drive(1) = 0.0;
    }
    const Eigen::Vector2cd states = A.partialPivLu().solve(drive);
    d.direct_damping = -d.dP_dgap_rate;
    d.film_damping = -(d.dP_dfilm * states(0)).imag() / w;
    d.loop_damping = back >= 0 ? -(Ps * states(1)).imag() / w : 0.0;
    const double mean_inlet_speed = 0.5 * (ref.bite.entry_speed + s.rolls.speed);
    d.squeeze_estimate = std::abs(d.dP_dfilm) * ref.bite.inlet_film /
                         (2.0 * ref.bite.inlet_angle * mean_inlet_speed);

    const ModalAnalysis modes = modal_analysis(mill, ref.strip_stiffness);
    double best = INFINITY;
    for (const NaturalMode& m : modes.natural) {
        const double gap = m.shape(2) - m.shape(3);
        const double distance = std::abs(m.frequency_Hz - d.frequency_Hz);
        if (distance < best && std::abs(gap) > 1e-12) {
            best = distance;
            d.gap_mass = 1.0 / (gap * gap);
        }
    }
    d.ok = true;
    d.message = "ok";
    return d;
}

}  // namespace rollgap::tools
