#include "core/mill/mill.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace rollgap::core {

Mill default_mill() {
    Mill m;
    m.stands.assign(5, Scenario{});
    m.thickness = {2.80e-3, 2.25e-3, 1.88e-3, 1.60e-3, 1.36e-3, 1.20e-3};
    m.span_length.assign(4, 5.0);
    m.interstand_tension.assign(4, 60e6);
    return m;
}

const char* to_string(MillSteadyStatus status) {
    switch (status) {
        case MillSteadyStatus::ok: return "ok";
        case MillSteadyStatus::no_steady_state: return "no_steady_state";
        case MillSteadyStatus::invalid: break;
    }
    return "invalid";
}

const char* mill_defect(const Mill& m) {
    const int n = m.size();
    if (n < 1 || n > max_mill_stands) return "a mill has 1 to 6 stands";
    if (static_cast<int>(m.thickness.size()) != n + 1)
        return "the schedule needs the entry thickness and one exit thickness per stand";
    for (int i = 0; i < n; ++i) {
        if (!(m.thickness[static_cast<std::size_t>(i + 1)] > 0.0) ||
            !(m.thickness[static_cast<std::size_t>(i + 1)] <
              m.thickness[static_cast<std::size_t>(i)]))
            return "the strip must get thinner at every stand";
    }
    if (static_cast<int>(m.span_length.size()) != n - 1 ||
        static_cast<int>(m.interstand_tension.size()) != n - 1)
        return "a mill of N stands has N - 1 interstand spans, each with a length and a tension";
    for (int i = 0; i + 1 < n; ++i) {
        if (!(m.span_length[static_cast<std::size_t>(i)] > 0.0))
            return "an interstand span needs a positive length";
        if (!(m.interstand_tension[static_cast<std::size_t>(i)] > 0.0))
            return "an interstand span needs a positive tension (at zero it is slack)";
    }
    if (m.entry == MillBoundary::span && (!(m.entry_span_length > 0.0) || !(m.entry_tension > 0.0)))
        return "an entry span needs a positive length and tension";
    if (m.exit == MillBoundary::span && (!(m.exit_span_length > 0.0) || !(m.exit_tension > 0.0)))
        return "an exit span needs a positive length and tension";
    if (m.entry_tension < 0.0 || m.exit_tension < 0.0) return "a tension cannot be compressive";
    if (!(m.speed > 0.0)) return "the mill speed must be positive";
    if (!(m.width > 0.0) || !(m.youngs_modulus > 0.0) || !(m.strip_density > 0.0))
        return "width, Young's modulus and density must be positive";
    if (m.span_model == SpanModel::segments &&
        (m.span_segments < 1 || m.span_segments > max_span_segments))
        return "a span has 1 to 50 segments";
    if (m.mode == MillMode::speeds) {
        for (const Scenario& stand : m.stands) {
            if (!(stand.rolls.speed > 0.0)) return "speeds mode needs every stand's roll speed";
        }
    }
    return "";
}

double back_tension_stress(const Mill& m, int stand) {
    return stand == 0 ? m.entry_tension : m.interstand_tension[static_cast<std::size_t>(stand - 1)];
}

double front_tension_stress(const Mill& m, int stand) {
    return stand + 1 == m.size() ? m.exit_tension
                                 : m.interstand_tension[static_cast<std::size_t>(stand)];
}

Scenario stand_scenario(const Mill& m, int stand, double roll_speed) {
    Scenario s = m.stands[static_cast<std::size_t>(stand)];
    const double y1 = m.thickness[static_cast<std::size_t>(stand)];
    const double y2 = m.thickness[static_cast<std::size_t>(stand + 1)];
    s.strip.entry_thickness = y1;
    s.strip.reduction = 1.0 - y2 / y1;
    s.strip.width = m.width;
    s.strip.youngs_modulus = m.youngs_modulus;
    s.rolls.speed = roll_speed;
    // the mill's spans carry the tensions: the stand sees them as given stresses
    s.tensions.back = TensionSide{TensionMode::constant, back_tension_stress(m, stand)};
    s.tensions.front = TensionSide{TensionMode::constant, front_tension_stress(m, stand)};
    return s;
}

namespace {

// The stand's steady bite at roll speed v (the flattened radius where the stand asks for it).
BiteResult steady_bite(const Mill& m, int stand, double v) {
    const Scenario s = stand_scenario(m, stand, v);
    return solve_roll_bite(s, steady_bite_state(s), {false});
}

MillStandState stand_state(const Mill& m, int stand, double v, const BiteResult& bite, int solves) {
    MillStandState out;
    out.status = bite.status;
    out.message = bite.message;
    out.roll_speed = v;
    out.bite_solves = solves;
    out.back_tension = back_tension_stress(m, stand);
    out.front_tension = front_tension_stress(m, stand);
    out.back_tension_force =
        out.back_tension * m.thickness[static_cast<std::size_t>(stand)] * m.width;
    out.front_tension_force =
        out.front_tension * m.thickness[static_cast<std::size_t>(stand + 1)] * m.width;
    if (bite.status != BiteStatus::ok) return out;
    out.entry_speed = bite.entry_speed;
    out.exit_speed = bite.exit_speed;
    out.forward_slip = bite.forward_slip;
    out.force = bite.force;
    out.torque = bite.torque;
    const double radius = m.stands[static_cast<std::size_t>(stand)].rolls.radius;
    out.power = 2.0 * bite.torque * v / radius;
    out.inlet_film = bite.inlet_film;
    out.neutral_point = bite.neutral_point;
    out.bite = bite;
    return out;
}

}  // namespace

std::vector<double> mill_roll_speeds(const Mill& m) {
    std::vector<double> speeds;
    if (m.stands.empty()) return speeds;
    const double scale = m.speed / m.stands.back().rolls.speed;
    for (const Scenario& stand : m.stands) speeds.push_back(stand.rolls.speed * scale);
    return speeds;
}

namespace {

// Speeds mode (§12.3): the roll speeds given, the interstand tension stresses sigma (N - 1)
// solve r_i = (u2_i y2_i - u2_N y2_N) / Q = 0 for i < N. Stand i's flow depends on sigma_{i-1}
// (its back) and sigma_i (its front), the last stand's on sigma_{N-1}: a difference column
// re-solves two stands. Newton with the step halved until every tension stays above a tenth of
// its value and |r| falls; a tension driven towards zero is a slack span (compression is not a
// steady state), a stand whose bite fails where the search must go is named.
MillSteadyState speeds_steady_state(const Mill& m) {
    MillSteadyState out;
    const int n = m.size();
    const std::vector<double> v = mill_roll_speeds(m);
    Mill trial = m;  // its interstand tensions are the iterate
    struct Flows {
        std::vector<BiteResult> bites;
        std::vector<double> r;  // N - 1 residuals, relative to the last stand's flow
        double norm = 0.0;
        int failed = -1;  // the stand whose bite failed
    };
    int solves = 0;
    BiteResult failure;  // the last bite that failed, for the stand it names
    const auto flow = [&](const BiteResult& b, int i) {
        return b.exit_speed * m.thickness[static_cast<std::size_t>(i + 1)];
    };
    const auto residuals = [&](Flows& f) {
        const double q = flow(f.bites.back(), n - 1);
        f.r.assign(static_cast<std::size_t>(n - 1), 0.0);
        f.norm = 0.0;
        for (int i = 0; i + 1 < n; ++i) {
            f.r[static_cast<std::size_t>(i)] =
                (flow(f.bites[static_cast<std::size_t>(i)], i) - q) / q;
            f.norm = std::max(f.norm, std::abs(f.r[static_cast<std::size_t>(i)]));
        }
    };
    const auto evaluate = [&](const std::vector<double>& sigma) {
        Flows f;
        trial.interstand_tension = sigma;
        f.bites.resize(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
            f.bites[static_cast<std::size_t>(i)] =
                steady_bite(trial, i, v[static_cast<std::size_t>(i)]);
            ++solves;
            if (f.bites[static_cast<std::size_t>(i)].status != BiteStatus::ok) {
                failure = f.bites[static_cast<std::size_t>(i)];
                f.failed = i;
                return f;
            }
        }
        residuals(f);
        return f;
    };
    std::vector<double> sigma = m.interstand_tension;
    Flows current = evaluate(sigma);
    const auto fail = [&](int stand, int span, const char* message) {
        out.status = MillSteadyStatus::no_steady_state;
        out.stand = stand;
        out.span = span;
        out.message = message;
        trial.interstand_tension = sigma;
        out.stands.resize(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) {
            const BiteResult b = i < static_cast<int>(current.bites.size())
                                     ? current.bites[static_cast<std::size_t>(i)]
                                     : BiteResult{};
            out.stands[static_cast<std::size_t>(i)] =
                stand_state(trial, i, v[static_cast<std::size_t>(i)], i == stand ? failure : b, 0);
        }
        return out;
    };
    if (current.failed >= 0)
        return fail(current.failed, -1,
                    "a stand has no steady state at its roll speed and the "
                    "starting tensions");
    constexpr double tolerance = 1e-13;
    constexpr int max_iterations = 40;
    int iteration = 0;
    std::vector<int> at_floor(static_cast<std::size_t>(n - 1), 0);  // steps held at sigma/10
    for (; iteration < max_iterations && current.norm > tolerance; ++iteration) {
        // the Jacobian dr/dsigma by forward differences: sigma_j moves stands j and j + 1
        Eigen::MatrixXd jac(n - 1, n - 1);
        for (int j = 0; j + 1 < n; ++j) {
            Flows moved = current;
            const double h = 1e-6 * sigma[static_cast<std::size_t>(j)];
            std::vector<double> s2 = sigma;
            s2[static_cast<std::size_t>(j)] += h;
            trial.interstand_tension = s2;
            for (const int i : {j, j + 1}) {
                moved.bites[static_cast<std::size_t>(i)] =
                    steady_bite(trial, i, v[static_cast<std::size_t>(i)]);
                ++solves;
                if (moved.bites[static_cast<std::size_t>(i)].status != BiteStatus::ok) {
                    failure = moved.bites[static_cast<std::size_t>(i)];
                    return fail(i, -1,
                                "a stand has no steady state near the tensions its roll "
                                "speed needs");
                }
            }
            residuals(moved);
            for (int i = 0; i + 1 < n; ++i)
                jac(i, j) = (moved.r[static_cast<std::size_t>(i)] -
                             current.r[static_cast<std::size_t>(i)]) /
                            h;
        }
        const Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(current.r.data(), n - 1);
        const Eigen::VectorXd step = jac.fullPivLu().solve(-r);
        if (!step.allFinite()) return fail(-1, -1, "the tensions' Newton step is singular");
        // damping: every tension above a tenth of its value, and |r| falling
        double lambda = 1.0;
        for (int j = 0; j + 1 < n; ++j) {
            const double s0 = sigma[static_cast<std::size_t>(j)];
            if (s0 + lambda * step(j) < 0.1 * s0) lambda = 0.9 * s0 / -step(j);
        }
        bool accepted = false;
        int failed = -1;
        for (int halving = 0; halving < 30; ++halving, lambda *= 0.5) {
            std::vector<double> next = sigma;
            for (int j = 0; j + 1 < n; ++j) next[static_cast<std::size_t>(j)] += lambda * step(j);
            Flows trial_flows = evaluate(next);
            if (trial_flows.failed >= 0) {
                failed = trial_flows.failed;
                continue;
            }
            if (trial_flows.norm < current.norm) {
                for (int j = 0; j + 1 < n; ++j) {
                    // a tension held at the floor while the full step wanted it below zero
                    const bool floored = sigma[static_cast<std::size_t>(j)] + step(j) <= 0.0;
                    at_floor[static_cast<std::size_t>(j)] =
                        floored ? at_floor[static_cast<std::size_t>(j)] + 1 : 0;
                }
                sigma = std::move(next);
                current = std::move(trial_flows);
                accepted = true;
                break;
            }
        }
        for (int j = 0; j + 1 < n; ++j) {
            if (at_floor[static_cast<std::size_t>(j)] >= 4)
                return fail(-1, j + 1, "the roll speeds drive an interstand span slack");
        }
        if (!accepted) {
            if (failed >= 0)
                return fail(failed, -1,
                            "a stand has no steady state on the way to the tensions "
                            "its roll speed needs");
            break;
        }
    }
    out.newton_iterations = iteration;
    if (!(current.norm <= 1e-10)) {
        // stalled: a tension at the floor is a span the speeds would compress
        for (int j = 0; j + 1 < n; ++j) {
            if (at_floor[static_cast<std::size_t>(j)] > 0)
                return fail(-1, j + 1, "the roll speeds drive an interstand span slack");
        }
        return fail(-1, -1, "the interstand tensions that carry one mass flow were not found");
    }
    trial.interstand_tension = sigma;
    out.stands.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
        out.stands[static_cast<std::size_t>(i)] =
            stand_state(trial, i, v[static_cast<std::size_t>(i)],
                        current.bites[static_cast<std::size_t>(i)], 0);
    out.stands.front().bite_solves = solves;  // the search's, over all stands
    const double q = flow(current.bites.back(), n - 1);
    out.mass_flow = q;
    for (int i = 0; i < n; ++i)
        out.mass_flow_residual =
            std::max(out.mass_flow_residual,
                     std::abs(flow(current.bites[static_cast<std::size_t>(i)], i) - q) / q);
    out.status = MillSteadyStatus::ok;
    out.message = "ok";
    return out;
}

}  // namespace

MillSteadyState mill_steady_state(const Mill& m) {
    MillSteadyState out;
    out.message = mill_defect(m);
    if (*out.message != '\0') return out;
    if (m.mode == MillMode::speeds) return speeds_steady_state(m);
    const int n = m.size();
    out.stands.resize(static_cast<std::size_t>(n));

    // the last stand at the mill speed sets the mass flow
    const BiteResult last = steady_bite(m, n - 1, m.speed);
    out.stands.back() = stand_state(m, n - 1, m.speed, last, 1);
    if (last.status != BiteStatus::ok) {
        out.status = MillSteadyStatus::no_steady_state;
        out.stand = n - 1;
        out.message = "the last stand has no steady state at the mill speed";
        return out;
    }
    const double Q = last.exit_speed * m.thickness.back();
    out.mass_flow = Q;

    // every other stand: u2(v) y2 = Q. u2 = v (1 + f(v)) with a forward slip f that moves slowly
    // with v: v = Q / (y2 (1 + f)) from the zero-slip guess, then the secant.
    for (int i = 0; i + 1 < n; ++i) {
        const double y2 = m.thickness[static_cast<std::size_t>(i + 1)];
        const auto flow_error = [&](const BiteResult& b) { return b.exit_speed * y2 - Q; };
        double v0 = Q / y2;
        BiteResult b0 = steady_bite(m, i, v0);
        int solves = 1;
        bool solved = b0.status == BiteStatus::ok;
        if (solved) {
            double v1 = Q / (y2 * (1.0 + b0.forward_slip));
            BiteResult b1 = steady_bite(m, i, v1);
            ++solves;
            double e0 = flow_error(b0);
            for (int k = 0; k < 30 && b1.status == BiteStatus::ok; ++k) {
                const double e1 = flow_error(b1);
                if (std::abs(e1) <= 1e-13 * Q || e1 == e0) break;
                const double v2 = v1 - e1 * (v1 - v0) / (e1 - e0);
                v0 = v1;
                e0 = e1;
                v1 = v2;
                b1 = steady_bite(m, i, v1);
                ++solves;
            }
            solved = b1.status == BiteStatus::ok && std::abs(flow_error(b1)) <= 1e-10 * Q;
            out.stands[static_cast<std::size_t>(i)] = stand_state(m, i, v1, b1, solves);
            if (b1.status == BiteStatus::ok && !solved) {
                out.stands[static_cast<std::size_t>(i)].status = BiteStatus::solver_failure;
                out.stands[static_cast<std::size_t>(i)].message =
                    "the roll speed that carries the mass flow was not found";
            }
        } else {
            out.stands[static_cast<std::size_t>(i)] = stand_state(m, i, v0, b0, solves);
        }
        if (!solved) {
            out.status = MillSteadyStatus::no_steady_state;
            out.stand = i;
            out.message = "a stand has no steady state at the mass flow of the last stand";
            return out;
        }
    }
    for (int i = 0; i < n; ++i) {
        const MillStandState& st = out.stands[static_cast<std::size_t>(i)];
        out.mass_flow_residual = std::max(
            out.mass_flow_residual,
            std::abs(st.exit_speed * m.thickness[static_cast<std::size_t>(i + 1)] - Q) / Q);
    }
    out.status = MillSteadyStatus::ok;
    out.message = "ok";
    return out;
}

}  // namespace rollgap::core
