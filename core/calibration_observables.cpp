#include "core/calibration_observables.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/coupled_model.h"
#include "core/roll_bite.h"

namespace rollgap::core {

const char* to_string(Observable quantity) {
    switch (quantity) {
        case Observable::roll_force: return "roll_force";
        case Observable::torque: return "torque";
        case Observable::forward_slip: return "forward_slip";
        case Observable::critical_speed: return "critical_speed";
        case Observable::chatter_frequency: return "chatter_frequency";
        case Observable::natural_frequency: return "natural_frequency";
        case Observable::damping_ratio: return "damping_ratio";
        case Observable::running_frequency: return "running_frequency";
        case Observable::running_damping_ratio: return "running_damping_ratio";
    }
    return "unknown";
}

bool needs_mode(Observable quantity) {
    return quantity == Observable::natural_frequency || quantity == Observable::damping_ratio;
}

namespace {

bool needs_bite(Observable q) {
    return q == Observable::roll_force || q == Observable::torque || q == Observable::forward_slip;
}
bool needs_critical(Observable q) {
    return q == Observable::critical_speed || q == Observable::chatter_frequency;
}
bool needs_running(Observable q) {
    return q == Observable::running_frequency || q == Observable::running_damping_ratio;
}

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Modal assurance criterion of two real shapes: 1 for the same shape, 0 for orthogonal ones.
double mac(const Vector6& a, const Vector6& b) {
    const double denominator = a.squaredNorm() * b.squaredNorm();
    return denominator > 0.0 ? std::min(1.0, a.dot(b) * a.dot(b) / denominator)
                             : 0.0;  // ≤ 1 in exact arithmetic
}

struct Modes {
    bool ok = false;
    std::string failure;
    ModalAnalysis modal;
};

// The stack's modes with the strip spring of the condition's steady bite, as the stability
// analysis reports them ("structure").
Modes modes_of(const Scenario& s) {
    Modes out;
    const ReferenceState reference = reference_state(dynamics_scenario(s), true);
    if (reference.status != BiteStatus::ok || !(reference.strip_stiffness > 0.0)) {
        out.failure =
            std::string("no steady bite for the strip spring: ") + to_string(reference.status);
        return out;
    }
    out.modal = modal_analysis(structure_matrices(s.structure), reference.strip_stiffness);
    out.ok = out.modal.ok && out.modal.natural.size() == 6;
    if (!out.ok) out.failure = "the modal analysis failed";
    return out;
}

struct Critical {
    bool ok = false;
    std::string failure;
    double speed = nan;
    double frequency_Hz = nan;
};

// The critical speed of the search, refined by secant steps on the largest growth rate (smooth
// in speed near a simple crossing). Without the refinement the search's tolerance (1e-4 of the
// speed) would be noise of that size in every finite difference.
Critical critical_of(const Scenario& s, const CriticalSpeedOptions& search,
                     const Control& control) {
    Critical out;
    // Only the critical speed is used: the scan may stop at the first crossing (§7.3).
    CriticalSpeedOptions to_crossing = search;
    to_crossing.stop_at_crossing = true;
    const CriticalSpeedResult found = critical_speed(s, to_crossing, control);
    if (found.status != CriticalSpeedStatus::found) {
        out.failure = std::string("no critical speed: ") + to_string(found.status);
        return out;
    }
    auto at = [&](double v) {
        Scenario moved = s;
        moved.rolls.speed = v;
        return stability_at(moved);
    };
    double v0 = found.critical_speed;
    SpeedStability p0 = at(v0);
    double v_best = v0;
    SpeedStability best = p0;
    if (p0.status == DynamicsStatus::ok) {
        const double reach =
            std::min(search.speed_step, 0.5);  // stay inside the bracketing scan step
        double v1 = v0 * (1.0 + std::max(search.relative_tolerance, 1e-7));
        SpeedStability p1 = at(v1);
        for (int k = 0; k < 6 && p1.status == DynamicsStatus::ok; ++k) {
            if (std::abs(p1.max_real_part) < std::abs(best.max_real_part)) {
                v_best = v1;
                best = p1;
            }
            const double slope = (p1.max_real_part - p0.max_real_part) / (v1 - v0);
            if (!(slope != 0.0) || !std::isfinite(slope)) break;
            const double v2 = v1 - p1.max_real_part / slope;
            if (!(std::abs(v2 - found.critical_speed) <= reach)) break;
            if (std::abs(v2 - v1) <= 1e-12 * v1) break;
            v0 = v1;
            p0 = p1;
            v1 = v2;
            p1 = at(v1);
        }
    }
    if (best.status != DynamicsStatus::ok) {
        out.failure = "no linearisation at the critical speed";
        return out;
    }
    out.speed = v_best;
    // The mode that crosses: the oscillatory eigenvalue with the largest real part; a real
    // eigenvalue crossing has no chatter frequency.
    out.frequency_Hz = best.least_damped.eigenvalue.real() >=
                               best.max_real_part - 1e-9 * (1.0 + std::abs(best.max_real_part))
                           ? best.least_damped.frequency_Hz
                           : nan;
    out.ok = true;
    return out;
}

struct ModeReference {
    Vector6 shape = Vector6::Zero();
    double frequency_Hz = nan;
};

class Predictor {
public:
    Predictor(const ScenarioCalibration& setup) : setup_(setup) {}

    // Chooses the modes at the start values; false (with `failure`) when that is impossible.
    bool choose_modes(std::string& failure) {
        references_.assign(setup_.observations.size(), ModeReference{});
        const Eigen::VectorXd x = start();
        for (std::size_t i = 0; i < setup_.observations.size(); ++i) {
            const ScenarioObservation& o = setup_.observations[i];
            if (!needs_mode(o.quantity)) continue;
            const Modes modes = modes_of(with(x, o.condition));
            if (!modes.ok) {
                failure =
                    "observation " + std::to_string(i) + ": at the start values " + modes.failure;
                return false;
            }
            std::size_t chosen = 0;
            if (o.mode.index >= 0) {
                chosen = static_cast<std::size_t>(std::min(o.mode.index, 5));
            } else {
                double distance = std::numeric_limits<double>::infinity();
                for (std::size_t k = 0; k < modes.modal.natural.size(); ++k) {
                    const double d = std::abs(modes.modal.natural[k].frequency_Hz - o.mode.near_Hz);
                    if (d < distance) {
                        distance = d;
                        chosen = k;
                    }
                }
            }
            references_[i] = {modes.modal.natural[chosen].shape,
                              modes.modal.natural[chosen].frequency_Hz};
        }
        return true;
    }

    Eigen::VectorXd start() const {
        Eigen::VectorXd x(static_cast<Eigen::Index>(setup_.parameters.size()));
        for (std::size_t j = 0; j < setup_.parameters.size(); ++j)
            x(static_cast<Eigen::Index>(j)) = setup_.parameters[j].start;
        return x;
    }

    Scenario with(const Eigen::VectorXd& x, int condition) const {
        Scenario s = setup_.conditions[static_cast<std::size_t>(condition)];
        for (std::size_t j = 0; j < setup_.access.size(); ++j)
            setup_.access[j](s) = x(static_cast<Eigen::Index>(j));
        return s;
    }

    std::vector<ObservationPrediction> predict(const Eigen::VectorXd& x,
                                               const Control& control) const {
        std::vector<ObservationPrediction> out(setup_.observations.size());
        for (std::size_t c = 0; c < setup_.conditions.size(); ++c) {
            if (control.should_stop()) break;
            const int condition = static_cast<int>(c);
            bool bite_needed = false, critical_needed = false, modes_needed = false,
                 running_needed = false;
            for (const auto& o : setup_.observations) {
                if (o.condition != condition) continue;
                bite_needed |= needs_bite(o.quantity);
                critical_needed |= needs_critical(o.quantity);
                modes_needed |= needs_mode(o.quantity);
                running_needed |= needs_running(o.quantity);
            }
            if (!bite_needed && !critical_needed && !modes_needed && !running_needed) continue;
            const Scenario s = with(x, condition);
            std::optional<BiteResult> bite;
            if (bite_needed)
                bite = solve_roll_bite(s, steady_bite_state(s), BiteOptions{false, -1.0});
            std::optional<Critical> critical;
            if (critical_needed) {
                critical = critical_of(s, setup_.critical_speed, control);
            }
            std::optional<Modes> modes;
            if (modes_needed) modes = modes_of(s);
            std::optional<SpeedStability> running;
            if (running_needed) running = stability_at(s);

            for (std::size_t i = 0; i < setup_.observations.size(); ++i) {
                const ScenarioObservation& o = setup_.observations[i];
                if (o.condition != condition) continue;
                ObservationPrediction& p = out[i];
                p.value = nan;
                if (needs_bite(o.quantity)) {
                    if (bite->status != BiteStatus::ok) {
                        p.failure = std::string("no steady bite: ") + to_string(bite->status);
                        continue;
                    }
                    p.value = o.quantity == Observable::roll_force ? bite->force
                              : o.quantity == Observable::torque   ? bite->torque
                                                                   : bite->forward_slip;
                } else if (needs_critical(o.quantity)) {
                    if (!critical->ok) {
                        p.failure = critical->failure;
                        continue;
                    }
                    p.value = o.quantity == Observable::critical_speed ? critical->speed
                                                                       : critical->frequency_Hz;
                    if (!std::isfinite(p.value))
                        p.failure = "the mode crossing at the critical speed is not oscillatory";
                } else if (needs_running(o.quantity)) {
                    if (running->steady_status != BiteStatus::ok ||
                        running->status != DynamicsStatus::ok || running->oscillatory.empty()) {
                        p.failure = "no linearisation of the running stand at its speed";
                        continue;
                    }
                    p.value = o.quantity == Observable::running_frequency
                                  ? running->least_damped.frequency_Hz
                                  : running->least_damped.damping_ratio;
                } else {
                    if (!modes->ok) {
                        p.failure = modes->failure;
                        continue;
                    }
                    follow_mode(*modes, references_[i], o.quantity, p);
                }
            }
        }
        return out;
    }

private:
    static void follow_mode(const Modes& modes, const ModeReference& reference, Observable quantity,
                            ObservationPrediction& p) {
        std::size_t best = 0;
        double best_mac = -1.0;
        for (std::size_t k = 0; k < modes.modal.natural.size(); ++k) {
            const double m = mac(modes.modal.natural[k].shape, reference.shape);
            if (m > best_mac) {
                best_mac = m;
                best = k;
            }
        }
        p.mode_frequency_Hz = reference.frequency_Hz;
        p.mode_mac = best_mac;
        const double natural = modes.modal.natural[best].frequency_Hz;
        if (quantity == Observable::natural_frequency) {
            p.value = natural;
            return;
        }
        // The damped modes carry only |displacement| per mass, which cannot tell a mode from
        // its mirror image; the damped mode of the followed natural mode is the one nearest
        // in frequency (damping ratios of a few per cent shift frequencies by ~0.1 %).
        double distance = std::numeric_limits<double>::infinity();
        for (const DampedMode& damped : modes.modal.damped) {
            const double d = std::abs(damped.frequency_Hz - natural);
            if (d < distance) {
                distance = d;
                p.value = damped.damping_ratio;
            }
        }
        if (!std::isfinite(distance))
            p.failure = "the mode is not oscillatory with the structure's damping";
    }

    const ScenarioCalibration& setup_;
    std::vector<ModeReference> references_;
};

}  // namespace

long stability_evaluations_per_prediction(const ScenarioCalibration& setup) {
    // A search scans its speeds and then bisects (Brent, ~20 evaluations at most for 1e-8 of
    // a 0.5 m/s bracket), then up to 8 refinement linearisations.
    const long scan = std::max(
        2L, static_cast<long>(
                std::ceil((setup.critical_speed.speed_max - setup.critical_speed.speed_min) /
                              std::min(setup.critical_speed.speed_step, 0.5) -
                          1e-9)) +
                1);
    long total = 0;
    for (std::size_t c = 0; c < setup.conditions.size(); ++c) {
        const bool critical =
            std::any_of(setup.observations.begin(), setup.observations.end(),
                        [&](const ScenarioObservation& o) {
                            return o.condition == static_cast<int>(c) && needs_critical(o.quantity);
                        });
        if (critical) total += scan + 30;
        const bool running =
            std::any_of(setup.observations.begin(), setup.observations.end(),
                        [&](const ScenarioObservation& o) {
                            return o.condition == static_cast<int>(c) && needs_running(o.quantity);
                        });
        if (running) total += 1;
    }
    return total;
}

std::vector<ObservationPrediction> predict_observations(const ScenarioCalibration& setup,
                                                        const Eigen::VectorXd& x,
                                                        const Control& control) {
    Predictor predictor(setup);
    std::string failure;
    if (!predictor.choose_modes(failure)) {
        std::vector<ObservationPrediction> out(setup.observations.size());
        for (auto& p : out) {
            p.value = nan;
            p.failure = failure;
        }
        return out;
    }
    return predictor.predict(x, control);
}

ScenarioCalibrationResult calibrate_scenario(const ScenarioCalibration& setup,
                                             const Control& control) {
    ScenarioCalibrationResult out;
    Predictor predictor(setup);
    std::string failure;
    if (!predictor.choose_modes(failure)) {
        out.fit.status = CalibrationStatus::model_failure;
        out.fit.values = predictor.start();
        out.predictions.assign(setup.observations.size(),
                               ObservationPrediction{nan, failure, 0.0, 0.0});
        return out;
    }
    const int m = static_cast<int>(setup.observations.size());
    const ResidualFunction residuals = [&](const Eigen::VectorXd& x, Eigen::VectorXd& r,
                                           const Control& inner) {
        const std::vector<ObservationPrediction> predicted = predictor.predict(x, inner);
        if (inner.should_stop()) return false;
        r.resize(m);
        for (int i = 0; i < m; ++i) {
            const ScenarioObservation& o = setup.observations[static_cast<std::size_t>(i)];
            const double value = predicted[static_cast<std::size_t>(i)].value;
            if (!std::isfinite(value)) return false;
            r(i) = (value - o.value) / o.uncertainty;
        }
        return true;
    };
    out.fit = calibrate(setup.parameters, m, residuals, setup.options, control,
                        setup.joint_prior ? &*setup.joint_prior : nullptr);
    if (out.fit.status != CalibrationStatus::cancelled)
        out.predictions = predictor.predict(out.fit.values, control);
    return out;
}

}  // namespace rollgap::core
