#include "core/stability.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/brent.h"
#include "core/parallel_for.h"

namespace rollgap::core {

const char* to_string(CriticalSpeedStatus status) {
    switch (status) {
        case CriticalSpeedStatus::found: return "found";
        case CriticalSpeedStatus::stable_in_range: return "stable_in_range";
        case CriticalSpeedStatus::unstable_at_lower_bound: return "unstable_at_lower_bound";
        case CriticalSpeedStatus::no_steady_state: return "no_steady_state";
        case CriticalSpeedStatus::cancelled: return "cancelled";
    }
    return "unknown";
}

Linearisation linearise(const DynamicModel& model, const Eigen::VectorXd& z, double t) {
    return model.jacobian(z, t);
}

namespace {

// Parlett-Reinsch balancing: a diagonal similarity D^-1 J D (powers of two, so exact) that
// evens out row and column norms. The Jacobian mixes metres, m/s, film and pascals (entries
// from 1e-13 to 1e14): unbalanced, the QR iteration returns eigenvalues wrong by O(10/s),
// enough to flip the stability verdict.
Eigen::VectorXd balancing_scales(Eigen::MatrixXd& A) {
    const Eigen::Index n = A.rows();
    Eigen::VectorXd scale = Eigen::VectorXd::Ones(n);
    bool converged = false;
    for (int sweep = 0; sweep < 100 && !converged; ++sweep) {
        converged = true;
        for (Eigen::Index i = 0; i < n; ++i) {
            double column = 0.0, row = 0.0;
            for (Eigen::Index j = 0; j < n; ++j) {
                if (j == i) continue;
                column += std::abs(A(j, i));
                row += std::abs(A(i, j));
            }
            if (column == 0.0 || row == 0.0) continue;
            double f = 1.0;
            const double total = column + row;
            while (column < row / 2.0) {
                column *= 2.0;
                row /= 2.0;
                f *= 2.0;
            }
            while (column >= row * 2.0) {
                column /= 2.0;
                row *= 2.0;
                f /= 2.0;
            }
            if ((column + row) < 0.95 * total) {
                converged = false;
                scale(i) *= f;
                A.row(i) /= f;
                A.col(i) *= f;
            }
        }
    }
    return scale;
}

}  // namespace

Eigensystem eigensystem(const Eigen::MatrixXd& jacobian) {
    Eigensystem out;
    Eigen::MatrixXd balanced = jacobian;
    const Eigen::VectorXd scale = balancing_scales(balanced);
    Eigen::EigenSolver<Eigen::MatrixXd> solver(balanced);
    if (solver.info() != Eigen::Success) return out;
    out.values = solver.eigenvalues();
    out.balanced_vectors = solver.eigenvectors();
    out.vectors = scale.cast<std::complex<double>>().asDiagonal() * out.balanced_vectors;
    out.scale = scale;
    out.ok = true;
    return out;
}

namespace {

// `stands` holds the eigenvector's part at each stand's six displacements (the output map). The
// shapes and displacements of all stands share one scale, so that they compare across stands; the
// chatter type is read on the stand that moves most.
Eigenmode make_mode(std::complex<double> lambda, const std::vector<Eigen::VectorXcd>& stands) {
    Eigenmode mode;
    mode.eigenvalue = lambda;
    mode.frequency_Hz = std::abs(lambda.imag()) / (2.0 * std::numbers::pi);
    const double magnitude = std::abs(lambda);
    mode.damping_ratio = magnitude > 0.0 ? -lambda.real() / magnitude : 1.0;
    std::size_t moving = 0;
    Eigen::Index k = 0;
    double largest = 0.0;
    for (std::size_t i = 0; i < stands.size(); ++i) {
        Eigen::Index at;
        const double stand_largest = stands[i].head<6>().cwiseAbs().maxCoeff(&at);
        if (i == 0 || stand_largest > largest) {
            largest = stand_largest;
            moving = i;
            k = at;
        }
    }
    mode.shapes.assign(stands.size(), Vector6::Zero());
    mode.displacements.assign(stands.size(), Vector6c::Zero());
    for (std::size_t i = 0; i < stands.size(); ++i) {
        const Vector6 shape = stands[i].head<6>().cwiseAbs();
        mode.shapes[i] = largest > 0.0 ? Vector6(shape / largest) : shape;
        if (largest > 0.0) mode.displacements[i] = stands[i].head<6>() / stands[moving](k);
    }
    mode.chatter = classify_chatter(mode.displacements[moving], mode.frequency_Hz);
    return mode;
}

// The speed, steady status, force and k4 of `s`; the eigenvalues of its coupled model.
SpeedStability analyse(const Scenario& scenario, bool with_strip_stiffness) {
    SpeedStability out;
    const Scenario s = dynamics_scenario(scenario);
    out.speed = s.rolls.speed;
    const ReferenceState ref = reference_state(s, with_strip_stiffness);
    out.steady_status = ref.status;
    if (ref.status != BiteStatus::ok) {
        out.status = DynamicsStatus::solver_failure;
        return out;
    }
    SpeedStability linear = linear_stability(CoupledModel(s, ref));
    linear.speed = out.speed;
    linear.steady_status = out.steady_status;
    linear.strip_stiffness = ref.strip_stiffness;
    linear.force = ref.bite.force;
    return linear;
}

Scenario at_speed(Scenario s, double speed) {
    s.rolls.speed = speed;
    return s;
}

bool usable(const SpeedStability& p) { return p.status == DynamicsStatus::ok; }

// Follows each oscillatory eigenvalue over the scan: every branch takes, at each speed, the
// unclaimed eigenvalue nearest (relatively) to its last frequency; leftovers start new branches.
std::vector<DampingBranch> track_branches(const std::vector<SpeedStability>& scan) {
    std::vector<DampingBranch> branches;
    for (const SpeedStability& point : scan) {
        if (!usable(point)) continue;
        std::vector<bool> claimed(point.oscillatory.size(), false);
        for (DampingBranch& branch : branches) {
            const double last = branch.frequency_Hz.back();
            int best = -1;
            double best_distance = 0.25;  // at most 25 % frequency change between scan points
            for (std::size_t k = 0; k < point.oscillatory.size(); ++k) {
                if (claimed[k]) continue;
                const double distance = std::abs(point.oscillatory[k].frequency_Hz - last) / last;
                if (distance < best_distance) {
                    best_distance = distance;
                    best = static_cast<int>(k);
                }
            }
            if (best < 0) continue;
            claimed[static_cast<std::size_t>(best)] = true;
            branch.speed.push_back(point.speed);
            branch.frequency_Hz.push_back(
                point.oscillatory[static_cast<std::size_t>(best)].frequency_Hz);
            branch.damping_ratio.push_back(
                point.oscillatory[static_cast<std::size_t>(best)].damping_ratio);
        }
        for (std::size_t k = 0; k < point.oscillatory.size(); ++k) {
            if (claimed[k]) continue;
            branches.push_back({{point.speed},
                                {point.oscillatory[k].frequency_Hz},
                                {point.oscillatory[k].damping_ratio}});
        }
    }
    std::sort(branches.begin(), branches.end(), [](const DampingBranch& a, const DampingBranch& b) {
        return a.frequency_Hz.front() < b.frequency_Hz.front();
    });
    return branches;
}

// What the first `n` speeds of a scan say: the lowest speed with a steady state (`n` if none)
// and the first pair of neighbouring speeds, both with a steady state, that goes from stable to
// unstable (its upper index; -1 if none). The outcome is decided once the lowest usable speed is
// unstable or such a pair exists: no speed above it changes the search (§7.3).
struct ScanReading {
    int first_usable = 0;
    int crossing = -1;
    bool decided = false;
};

ScanReading read_scan(const std::vector<SpeedStability>& scan, int n) {
    ScanReading reading;
    while (reading.first_usable < n &&
           !usable(scan[static_cast<std::size_t>(reading.first_usable)]))
        ++reading.first_usable;
    if (reading.first_usable == n) return reading;
    reading.decided = !scan[static_cast<std::size_t>(reading.first_usable)].stable;
    if (reading.decided) return reading;
    for (int i = reading.first_usable + 1; i < n && reading.crossing < 0; ++i) {
        const SpeedStability& previous = scan[static_cast<std::size_t>(i - 1)];
        const SpeedStability& p = scan[static_cast<std::size_t>(i)];
        if (usable(previous) && usable(p) && previous.stable && !p.stable) reading.crossing = i;
    }
    reading.decided = reading.crossing >= 0;
    return reading;
}

}  // namespace

Eigen::VectorXcd balanced_eigenvalues(const Eigen::MatrixXd& jacobian) {
    const Eigensystem system = eigensystem(jacobian);
    return system.ok ? system.values : Eigen::VectorXcd();
}

SpeedStability linear_stability(const DynamicModel& model) {
    SpeedStability out;
    const Linearisation lin = linearise(model, model.equilibrium());
    out.status = lin.status;
    if (lin.status != DynamicsStatus::ok) return out;

    const Eigensystem eig = eigensystem(lin.jacobian);
    if (!eig.ok) {
        out.status = DynamicsStatus::solver_failure;
        return out;
    }
    out.max_real_part = -std::numeric_limits<double>::infinity();
    double best_oscillatory = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < eig.values.size(); ++i) {
        const std::complex<double> lambda = eig.values(i);
        out.eigenvalues.push_back(lambda);
        out.max_real_part = std::max(out.max_real_part, lambda.real());
        if (lambda.imag() > 0.0) {
            std::vector<Eigen::VectorXcd> stands;
            for (int j = 0; j < model.stand_count(); ++j)
                stands.emplace_back(eig.vectors.col(i).segment(model.displacement_index(j), 6));
            const Eigenmode mode = make_mode(lambda, stands);
            out.oscillatory.push_back(mode);
            if (lambda.real() > best_oscillatory) {
                best_oscillatory = lambda.real();
                out.least_damped = mode;
            }
        }
    }
    std::sort(
        out.oscillatory.begin(), out.oscillatory.end(),
        [](const Eigenmode& a, const Eigenmode& b) { return a.frequency_Hz < b.frequency_Hz; });
    out.stable = out.max_real_part < 0.0;
    return out;
}

SpeedStability stability_at(const Scenario& s) { return analyse(s, true); }

CriticalSpeedResult critical_speed(const Scenario& s, const CriticalSpeedOptions& options,
                                   const Control& control) {
    const auto at = [&s](double speed, bool with_strip_stiffness) {
        return analyse(at_speed(s, speed), with_strip_stiffness);
    };
    return critical_speed_search(at, options, control);
}

CriticalSpeedResult critical_speed_search(const StabilityAtSpeed& analyse_at,
                                          const CriticalSpeedOptions& options,
                                          const Control& control) {
    CriticalSpeedResult result;
    const double step = std::min(options.speed_step, 0.5);
    const int count = std::max(
        2, static_cast<int>(std::ceil((options.speed_max - options.speed_min) / step - 1e-9)) + 1);
    std::vector<double> speeds(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        speeds[static_cast<std::size_t>(i)] =
            std::min(options.speed_max, options.speed_min + i * step);
    }

    result.scan.resize(speeds.size());
    std::atomic<int> done{0};
    // The scan in blocks of grid speeds, each block in parallel. Whole at once unless the search
    // may stop at the first crossing: then block after block, in grid order, until a block
    // decides the outcome (the first usable speed unstable, or a stable-to-unstable pair). Which
    // speeds are scanned depends on the block size, the outcome does not: it is decided by the
    // speeds up to the crossing, which every block size scans.
    const int block = options.stop_at_crossing ? std::max(2, control.thread_budget()) : count;
    int scanned = 0;
    bool decided = false;
    while (scanned < count && !decided) {
        const int begin = scanned;
        const int end = std::min(count, begin + block);
        parallel_for(end - begin, control, [&](int k) {
            if (control.should_stop()) return;
            const int i = begin + k;
            SpeedStability point = analyse_at(speeds[static_cast<std::size_t>(i)], false);
            result.scan[static_cast<std::size_t>(i)] = std::move(point);
            control.report(0.9 * (++done) / count);
        });
        if (control.should_stop()) break;
        scanned = end;
        if (!options.stop_at_crossing) break;
        decided = read_scan(result.scan, scanned).decided;
    }
    if (control.should_stop()) {
        result.status = CriticalSpeedStatus::cancelled;
        return result;
    }
    result.scan.resize(static_cast<std::size_t>(scanned));
    result.branches = track_branches(result.scan);

    // The lowest speed with a steady state decides whether the range starts stable; then the
    // first pair of neighbouring scan speeds, both with a steady state, that straddles zero. A
    // speed without a steady state (skidding, contact lost) is never bracketed across.
    auto strip_modes = [&] {
        for (auto& point : result.scan) point.oscillatory.clear();
    };
    const ScanReading reading = read_scan(result.scan, scanned);
    const int first = reading.first_usable, crossing = reading.crossing;
    if (first == scanned) {
        result.status = CriticalSpeedStatus::no_steady_state;
        strip_modes();
        return result;
    }
    if (!result.scan[static_cast<std::size_t>(first)].stable) {
        result.status = CriticalSpeedStatus::unstable_at_lower_bound;
        result.unstable_mode = result.scan[static_cast<std::size_t>(first)].least_damped;
        strip_modes();
        return result;
    }
    if (crossing < 0) {
        result.status = CriticalSpeedStatus::stable_in_range;
        strip_modes();
        return result;
    }

    const SpeedStability& lo = result.scan[static_cast<std::size_t>(crossing - 1)];
    const SpeedStability& hi = result.scan[static_cast<std::size_t>(crossing)];
    auto growth = [&](double v) {
        const SpeedStability p = analyse_at(v, false);
        return usable(p) ? p.max_real_part : std::nan("");
    };
    const RootResult root = brent_root(growth, lo.speed, hi.speed, lo.max_real_part,
                                       hi.max_real_part, options.relative_tolerance * lo.speed);
    if (!root.converged) {
        // the growth rate is not continuous here (a steady state is lost inside the interval):
        // report the first unstable scan speed
        result.critical_speed = hi.speed;
        result.unstable_mode = hi.least_damped;
    } else {
        result.critical_speed = root.x;
        const SpeedStability at = analyse_at(root.x, true);
        result.unstable_mode = at.least_damped;
        // the mode that crosses: the eigenvalue with the largest real part, oscillatory or not
        if (at.max_real_part > at.least_damped.eigenvalue.real()) {
            for (const auto& lambda : at.eigenvalues) {
                if (lambda.real() == at.max_real_part)
                    result.unstable_mode = make_mode(
                        lambda, std::vector<Eigen::VectorXcd>(at.least_damped.shapes.size(),
                                                              Eigen::VectorXcd::Zero(6)));
            }
        }
    }
    result.status = CriticalSpeedStatus::found;
    strip_modes();
    control.report(1.0);
    return result;
}

}  // namespace rollgap::core
