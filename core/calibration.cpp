#include "core/calibration.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/parallel_for.h"

namespace rollgap::core {

const char* to_string(CalibrationStatus status) {
    switch (status) {
        case CalibrationStatus::converged: return "converged";
        case CalibrationStatus::max_iterations: return "max_iterations";
        case CalibrationStatus::max_evaluations: return "max_evaluations";
        case CalibrationStatus::stalled: return "stalled";
        case CalibrationStatus::model_failure: return "model_failure";
        case CalibrationStatus::cancelled: return "cancelled";
    }
    return "unknown";
}

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

class Fit {
public:
    Fit(const std::vector<CalibrationParameter>& parameters, int observation_count,
        const ResidualFunction& model, const CalibrationOptions& options, const Control& control,
        const JointPrior* joint)
        : p_(parameters), m_(observation_count), n_(static_cast<int>(parameters.size())),
          model_(model), options_(options), control_(control), joint_(joint) {
        if (joint_ != nullptr) joint_factor_ = joint_->covariance.llt().matrixL();
        lower_.resize(n_);
        upper_.resize(n_);
        scale_.resize(n_);
        for (int j = 0; j < n_; ++j) {
            const auto& parameter = p_[static_cast<std::size_t>(j)];
            lower_(j) = parameter.lower;
            upper_(j) = parameter.upper;
            // The size a step is measured against: the value itself, unless it is near zero
            // relative to its range.
            scale_(j) =
                std::max(std::abs(parameter.start), 1e-3 * (parameter.upper - parameter.lower));
        }
    }

    CalibrationResult run();

private:
    // Observations then priors: the full weighted residual vector.
    int rows() const { return m_ + n_; }

    bool evaluate(const VectorXd& x, VectorXd& r, int threads) {
        if (evaluations_.load() >= options_.max_evaluations) return false;
        ++evaluations_;
        const Control inner = control_.nested(threads);
        r.resize(rows());
        VectorXd observed(m_);
        if (!model_(x, observed, inner) || !observed.allFinite()) return false;
        r.head(m_) = observed;
        for (int j = 0; j < n_; ++j) {
            const auto& parameter = p_[static_cast<std::size_t>(j)];
            r(m_ + j) = parameter.has_prior
                            ? (x(j) - parameter.prior_value) / parameter.prior_uncertainty
                            : 0.0;
        }
        if (joint_ != nullptr) {
            // whitened: L⁻¹ (x_S − mean), its k-th row in the slot of the k-th covered parameter
            VectorXd d(static_cast<Eigen::Index>(joint_->indices.size()));
            for (std::size_t k = 0; k < joint_->indices.size(); ++k)
                d(static_cast<Eigen::Index>(k)) =
                    x(joint_->indices[k]) - joint_->mean(static_cast<Eigen::Index>(k));
            const VectorXd w = joint_factor_.triangularView<Eigen::Lower>().solve(d);
            for (std::size_t k = 0; k < joint_->indices.size(); ++k)
                r(m_ + joint_->indices[k]) = w(static_cast<Eigen::Index>(k));
        }
        return true;
    }

    // Forward differences, the columns in parallel on the executor, each evaluation's inner
    // loops sharing what is left of the budget; a step that would leave the box goes the
    // other way. The prior rows are exact. False if a column has no model answer either way.
    bool jacobian(const VectorXd& x, const VectorXd& r, MatrixXd& J, double progress_from,
                  double progress_span) {
        J = MatrixXd::Zero(rows(), n_);
        std::vector<char> ok(static_cast<std::size_t>(n_), 0);
        const int threads = control_.thread_budget();
        const int inner_threads = std::max(1, threads / std::max(1, n_));
        std::atomic<int> done{0};
        parallel_for(n_, control_, [&](int j) {
            if (control_.should_stop()) return;
            const double h = options_.relative_step * std::max(std::abs(x(j)), scale_(j));
            for (const double direction : {1.0, -1.0}) {
                VectorXd moved = x;
                moved(j) = std::clamp(x(j) + direction * h, lower_(j), upper_(j));
                const double step = moved(j) - x(j);
                if (step == 0.0) continue;
                VectorXd rj;
                if (!evaluate(moved, rj, inner_threads)) continue;
                J.col(j) = (rj - r) / step;
                ok[static_cast<std::size_t>(j)] = 1;
                break;
            }
            control_.report(progress_from + progress_span * (++done) / n_);
        });
        return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
    }

    bool stop_requested() const { return control_.should_stop(); }

    void fill_statistics(CalibrationResult& result, const VectorXd& x, const VectorXd& r,
                         const MatrixXd& J) const;

    const std::vector<CalibrationParameter>& p_;
    int m_, n_;
    const ResidualFunction& model_;
    CalibrationOptions options_;
    const Control& control_;
    const JointPrior* joint_;
    MatrixXd joint_factor_;  // L of the joint prior's covariance
    VectorXd lower_, upper_, scale_;
    std::atomic<int> evaluations_{0};
};

CalibrationResult Fit::run() {
    CalibrationResult result;
    VectorXd x(n_);
    for (int j = 0; j < n_; ++j)
        x(j) = std::clamp(p_[static_cast<std::size_t>(j)].start, lower_(j), upper_(j));
    result.values = x;
    result.standard_errors = VectorXd::Constant(n_, std::numeric_limits<double>::infinity());
    result.correlation = MatrixXd::Constant(n_, n_, std::nan(""));
    result.degrees_of_freedom = m_ - n_;
    result.bounds.assign(static_cast<std::size_t>(n_), BoundState::inside);

    auto finish = [&](CalibrationStatus status) {
        result.status = status;
        result.evaluations = evaluations_.load();
        if (status != CalibrationStatus::cancelled) control_.report(1.0);
        return result;
    };

    VectorXd r;
    if (!evaluate(x, r, control_.thread_budget())) {
        return finish(stop_requested() ? CalibrationStatus::cancelled
                                       : CalibrationStatus::model_failure);
    }
    double cost = r.squaredNorm();
    double lambda = -1.0, nu = 2.0;
    MatrixXd J;
    const double per_iteration = 1.0 / (options_.max_iterations + 1);
    CalibrationStatus status = CalibrationStatus::max_iterations;
    bool jacobian_current = false;

    for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
        if (stop_requested()) return finish(CalibrationStatus::cancelled);
        if (!jacobian(x, r, J, iteration * per_iteration, per_iteration)) {
            if (stop_requested()) return finish(CalibrationStatus::cancelled);
            status = evaluations_.load() >= options_.max_evaluations
                         ? CalibrationStatus::max_evaluations
                         : CalibrationStatus::stalled;
            break;
        }
        jacobian_current = true;
        result.iterations = iteration + 1;
        const MatrixXd A = J.transpose() * J;
        const VectorXd g = J.transpose() * r;  // half the gradient of the cost

        // Active set: a parameter on a bound that the descent direction pushes outward is held.
        std::vector<int> free;
        for (int j = 0; j < n_; ++j) {
            const bool held =
                (x(j) <= lower_(j) && g(j) > 0.0) || (x(j) >= upper_(j) && g(j) < 0.0);
            if (!held) free.push_back(j);
        }
        const int nf = static_cast<int>(free.size());
        if (nf == 0) {
            status = CalibrationStatus::converged;
            break;
        }
        MatrixXd Af(nf, nf);
        VectorXd gf(nf), diag(nf);
        for (int a = 0; a < nf; ++a) {
            gf(a) = g(free[static_cast<std::size_t>(a)]);
            for (int b = 0; b < nf; ++b)
                Af(a, b) = A(free[static_cast<std::size_t>(a)], free[static_cast<std::size_t>(b)]);
        }
        const double largest = Af.diagonal().maxCoeff();
        if (!(largest > 0.0)) {
            status = CalibrationStatus::converged;  // nothing depends on the free parameters
            break;
        }
        // Marquardt's scaling: the damping term follows each parameter's own curvature, so
        // the step does not depend on the parameters' units.
        for (int a = 0; a < nf; ++a) diag(a) = std::max(Af(a, a), 1e-12 * largest);
        if (lambda < 0.0) lambda = 1e-3;

        bool accepted = false, done = false;
        for (int attempt = 0; attempt < 12 && !accepted; ++attempt) {
            if (stop_requested()) return finish(CalibrationStatus::cancelled);
            MatrixXd damped = Af;
            damped.diagonal() += lambda * diag;
            const VectorXd delta_f = damped.ldlt().solve(-gf);
            VectorXd trial = x;
            for (int a = 0; a < nf; ++a) {
                const int j = free[static_cast<std::size_t>(a)];
                trial(j) = std::clamp(x(j) + delta_f(a), lower_(j), upper_(j));
            }
            const VectorXd step = trial - x;
            bool small = true;
            for (int j = 0; j < n_; ++j) {
                if (std::abs(step(j)) >
                    options_.step_tolerance * std::max(std::abs(x(j)), scale_(j)))
                    small = false;
            }
            if (small) {
                done = true;
                break;
            }
            VectorXd trial_r;
            if (!evaluate(trial, trial_r, control_.thread_budget())) {
                if (stop_requested()) return finish(CalibrationStatus::cancelled);
                if (evaluations_.load() >= options_.max_evaluations) {
                    status = CalibrationStatus::max_evaluations;
                    done = true;
                    break;
                }
                lambda *= nu;
                nu *= 2.0;
                continue;
            }
            const double trial_cost = trial_r.squaredNorm();
            // The decrease the linear model predicts for this step (cost = |r|², not ½|r|²).
            const double predicted = -(2.0 * g.dot(step) + step.dot(A * step));
            if (trial_cost < cost) {
                const double rho = predicted > 0.0 ? (cost - trial_cost) / predicted : 1.0;
                // Nielsen's update, but down by up to 10 (not 3) on a good step: along a nearly
                // flat valley (the flow stress against the asperity factor) the step is
                // λ-limited, and a slow decrease of λ costs a Jacobian per factor of 3.
                lambda *= std::max(0.1, 1.0 - std::pow(2.0 * rho - 1.0, 3));
                nu = 2.0;
                const double decrease = cost - trial_cost;
                x = trial;
                r = trial_r;
                cost = trial_cost;
                accepted = true;
                jacobian_current = false;
                if (decrease <= options_.cost_tolerance * cost || cost == 0.0) done = true;
            } else {
                lambda *= nu;
                nu *= 2.0;
            }
        }
        if (done) {
            if (status != CalibrationStatus::max_evaluations) status = CalibrationStatus::converged;
            break;
        }
        if (!accepted) {
            status = CalibrationStatus::stalled;
            break;
        }
    }

    // Statistics need the Jacobian at the solution itself.
    if (!jacobian_current) {
        Eigen::MatrixXd final_jacobian;
        const int budget = options_.max_evaluations;
        options_.max_evaluations =
            evaluations_.load() + 2 * n_;  // the final Jacobian is always allowed
        const bool ok = jacobian(x, r, final_jacobian, 1.0 - per_iteration, per_iteration);
        options_.max_evaluations = budget;
        if (stop_requested()) return finish(CalibrationStatus::cancelled);
        if (ok) J = final_jacobian;
        jacobian_current = ok;
    }
    result.values = x;
    result.residuals = r.head(m_);
    result.prior_residuals = r.tail(n_);
    result.chi_squared_observations = r.head(m_).squaredNorm();
    result.chi_squared_priors = r.tail(n_).squaredNorm();
    for (int j = 0; j < n_; ++j) {
        result.bounds[static_cast<std::size_t>(j)] = x(j) <= lower_(j)   ? BoundState::lower
                                                     : x(j) >= upper_(j) ? BoundState::upper
                                                                         : BoundState::inside;
    }
    if (jacobian_current && J.rows() == rows()) fill_statistics(result, x, r, J);
    return finish(status);
}

// Eigen-decomposition of a normal matrix after scaling it to unit diagonal (a correlation-like
// matrix): its smallest eigenvalues say which combinations of parameters are not determined,
// whatever the parameters' units.
struct ScaledNormal {
    VectorXd scale;  // sqrt of the diagonal (0: the column is zero)
    Eigen::SelfAdjointEigenSolver<MatrixXd> eigen;
};

ScaledNormal scaled_normal(const MatrixXd& normal) {
    ScaledNormal out;
    out.scale = normal.diagonal().cwiseMax(0.0).cwiseSqrt();
    const Eigen::Index n = normal.rows();
    MatrixXd scaled = MatrixXd::Identity(n, n);
    for (Eigen::Index a = 0; a < n; ++a) {
        for (Eigen::Index b = 0; b < n; ++b) {
            if (out.scale(a) > 0.0 && out.scale(b) > 0.0)
                scaled(a, b) = normal(a, b) / (out.scale(a) * out.scale(b));
        }
    }
    out.eigen.compute(scaled);
    return out;
}

void Fit::fill_statistics(CalibrationResult& result, const VectorXd&, const VectorXd&,
                          const MatrixXd& J) const {
    // Posterior covariance (JᵀJ)⁻¹ with the prior rows, through the scaled eigen-decomposition;
    // directions with no information (eigenvalue at rounding level) make the standard errors
    // of the parameters in them infinite instead of huge-but-finite noise.
    const ScaledNormal posterior = scaled_normal(J.transpose() * J);
    const VectorXd mu = posterior.eigen.eigenvalues();
    const MatrixXd V = posterior.eigen.eigenvectors();
    const double mu_max = std::max(mu.maxCoeff(), std::numeric_limits<double>::min());
    MatrixXd covariance_scaled = MatrixXd::Zero(n_, n_);
    std::vector<bool> undetermined(static_cast<std::size_t>(n_), false);
    for (int k = 0; k < n_; ++k) {
        if (mu(k) > 1e-12 * mu_max) {
            covariance_scaled += V.col(k) * V.col(k).transpose() / mu(k);
        } else {
            for (int j = 0; j < n_; ++j) {
                if (std::abs(V(j, k)) > 1e-3) undetermined[static_cast<std::size_t>(j)] = true;
            }
        }
    }
    for (int j = 0; j < n_; ++j) {
        if (posterior.scale(j) == 0.0) undetermined[static_cast<std::size_t>(j)] = true;
    }
    for (int a = 0; a < n_; ++a) {
        const bool a_known = !undetermined[static_cast<std::size_t>(a)];
        result.standard_errors(a) = a_known
                                        ? std::sqrt(covariance_scaled(a, a)) / posterior.scale(a)
                                        : std::numeric_limits<double>::infinity();
        for (int b = 0; b < n_; ++b) {
            const bool b_known = !undetermined[static_cast<std::size_t>(b)];
            result.correlation(a, b) =
                a_known && b_known ? covariance_scaled(a, b) / std::sqrt(covariance_scaled(a, a) *
                                                                         covariance_scaled(b, b))
                                   : (a == b ? 1.0 : std::nan(""));
        }
    }

    // What the observations alone determine (the priors may hide it in the posterior).
    const MatrixXd observations = J.topRows(m_);
    const ScaledNormal data = scaled_normal(observations.transpose() * observations);
    for (int j = 0; j < n_; ++j) {
        if (data.scale(j) == 0.0) result.unobservable.push_back(j);
    }
    const VectorXd nu = data.eigen.eigenvalues();  // ascending
    const MatrixXd W = data.eigen.eigenvectors();
    const double nu_max = nu.maxCoeff();
    result.reciprocal_condition = nu_max > 0.0 ? std::max(0.0, nu.minCoeff()) / nu_max : 0.0;
    for (int k = 0; k < n_; ++k) {
        if (nu_max > 0.0 && nu(k) >= options_.separability_limit * nu_max) continue;
        std::vector<int> group;
        for (int j = 0; j < n_; ++j) {
            const bool observed = data.scale(j) > 0.0;
            // A parameter with a large share of the null direction (|v_j| ≥ 0.2: at least
            // 4 % of its squared length) is one the observations trade against the others.
            if (observed && std::abs(W(j, k)) >= 0.2) group.push_back(j);
        }
        if (group.size() >= 2) result.inseparable.push_back(std::move(group));
    }
}

}  // namespace

CalibrationResult calibrate(const std::vector<CalibrationParameter>& parameters,
                            int observation_count, const ResidualFunction& residuals,
                            const CalibrationOptions& options, const Control& control,
                            const JointPrior* joint_prior) {
    Fit fit(parameters, observation_count, residuals, options, control, joint_prior);
    return fit.run();
}

}  // namespace rollgap::core
