#include "core/mill/mill_time.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "core/cvode_support.h"

namespace rollgap::core {

const char* to_string(MillTimeStatus status) {
    switch (status) {
        case MillTimeStatus::ok: return "ok";
        case MillTimeStatus::slack_span: return "slack_span";
        case MillTimeStatus::contact_lost: return "contact_lost";
        case MillTimeStatus::skidding: return "skidding";
        case MillTimeStatus::solver_failure: return "solver_failure";
        case MillTimeStatus::step_budget: return "step_budget";
        case MillTimeStatus::cancelled: return "cancelled";
        case MillTimeStatus::invalid: return "invalid";
    }
    return "invalid";
}

namespace {

// One accepted step of the stand delivering into a span: the strip position S = int u2 dt and
// its rate u2, the exit thickness's deviation y2 - y2_ref and its first two derivatives.
struct Node {
    double t = 0.0;
    double position = 0.0;      // S, m
    double speed = 0.0;         // S' = u2, m/s
    double thickness = 0.0;     // y2 - y2_ref, m
    double rate = 0.0;          // y2', m/s
    double acceleration = 0.0;  // y2'', m/s^2
};

// What the stand downstream sees of the strip that left at t_d.
struct Delayed {
    bool ok = false;
    double departure = 0.0;  // t_d, s
    double thickness = 0.0;  // y2(t_d) - y2_ref, m
    double rate = 0.0;       // y2'(t_d), m/s
    double speed = 0.0;      // u2(t_d), m/s
};

// Cubic Hermite interpolation on [0, 1] of the values p0, p1 with slopes m0, m1 (per unit of the
// parameter): the value and its derivative.
struct Hermite {
    double value, slope;
};
Hermite hermite(double p0, double m0, double p1, double m1, double x) {
    const double x2 = x * x, x3 = x2 * x;
    return {(2 * x3 - 3 * x2 + 1) * p0 + (x3 - 2 * x2 + x) * m0 + (-2 * x3 + 3 * x2) * p1 +
                (x3 - x2) * m1,
            (6 * x2 - 6 * x) * p0 + (3 * x2 - 4 * x + 1) * m0 + (-6 * x2 + 6 * x) * p1 +
                (3 * x2 - 2 * x) * m1};
}

// A span's history of the strip leaving its upstream stand (docs/model.md §12.9, specification
// §3): nodes at CVODE's accepted steps, S increasing along them (u2 > 0 while the stand rolls).
// Before the start (t = 0, S = 0) the strip left at the steady thickness and speed.
class History {
public:
    History(double length, double steady_speed) : length_(length), steady_speed_(steady_speed) {}

    void append(const Node& node) { nodes_.push_back(node); }

    // The strip at stand i+1 when stand i's strip position is `position` (S_i(t)): it left stand i
    // where S_i(t_d) = S_i(t) - L_i.
    Delayed at(double position) const {
        Delayed out;
        const double target = position - length_;
        if (target < 0.0) {
            // before the start: the steady strip, S extrapolated at the steady speed
            out.ok = true;
            out.departure = target / steady_speed_;
            out.speed = steady_speed_;
            return out;
        }
        // (pruning keeps 1.5 L behind the last node: a target before the first node cannot
        // happen, nor one with no node yet, as the start's node is recorded before any step)
        if (nodes_.empty() || target < nodes_.front().position) return out;
        if (target >= nodes_.back().position) {
            // only at the last node itself; beyond it the step would exceed the delay
            if (target > nodes_.back().position) return out;
            const Node& last = nodes_.back();
            return {true, last.t, last.thickness, last.rate, last.speed};
        }
        // the first node past the target, and the one before it
        const auto next =
            std::upper_bound(nodes_.begin(), nodes_.end(), target,
                             [](double s, const Node& node) { return s < node.position; });
        const Node& b = *next;
        const Node& a = *(next - 1);
        const double h = b.t - a.t;
        // S(x) = target on the cubic Hermite of S over the step, x in [0, 1]: Newton kept inside
        // a shrinking bracket (S(0) <= target < S(1)), bisection when Newton leaves it
        double lo = 0.0, hi = 1.0;
        double x = (target - a.position) / (b.position - a.position);
        for (int k = 0; k < 60; ++k) {
            const Hermite s = hermite(a.position, h * a.speed, b.position, h * b.speed, x);
            const double f = s.value - target;
            if (f < 0.0) lo = x;
            else hi = x;
            if (std::abs(f) <= 1e-15 * std::max(1.0, std::abs(target)) || hi - lo < 1e-15) break;
            double next_x = s.slope > 0.0 ? x - f / s.slope : 0.5 * (lo + hi);
            if (!(next_x > lo && next_x < hi)) next_x = 0.5 * (lo + hi);
            x = next_x;
        }
        const Hermite y = hermite(a.thickness, h * a.rate, b.thickness, h * b.rate, x);
        const Hermite rate = hermite(a.rate, h * a.acceleration, b.rate, h * b.acceleration, x);
        const Hermite s = hermite(a.position, h * a.speed, b.position, h * b.speed, x);
        out.ok = true;
        out.departure = a.t + x * h;
        out.thickness = y.value;
        out.rate = rate.value;
        out.speed = s.slope / h;
        return out;
    }

    // Forgets the nodes no future lookup reaches: every later S(t) is at least the last node's,
    // so t_d lies past S_last - L; 1.5 L keeps a margin for the root finder's and the outputs'
    // interpolated states inside the last step (S moves by at most ~L/4 over a step).
    void prune() {
        const double keep = nodes_.back().position - 1.5 * length_;
        while (nodes_.size() > 2 && nodes_[1].position < keep) nodes_.pop_front();
    }

private:
    std::deque<Node> nodes_;
    double length_;
    double steady_speed_;
};

// Trial steps that overshoot into a limit are few in a healthy run (time_integration.cpp).
constexpr int limit_failure_budget = 100;

// One run: the model, the spans' histories and the scratch of the right-hand side.
struct Run {
    const MillModel* model = nullptr;
    int n = 0;             // the mill model's states; the strip positions follow
    int stands = 0;        // N
    int spans = 0;         // N - 1 interstand spans
    int span_margins = 0;  // the model's span margins (the stands' contact margins follow)
    int first_span = 0;    // the span number (behind-stand) of the model's first span margin
    bool frozen = false;
    std::vector<History> history;
    std::vector<double> steady_speed;  // u2_i,ref of the stand delivering into span i
    std::vector<double> deviation, rate_per_speed, exit_speed, transport_time;
    DynamicsStatus last_failure = DynamicsStatus::ok;
    MillFailure where;
    const char* detail = nullptr;  // a lookup past the history (not a physical limit)
    int limit_failures = 0;
    long fallback_rhs_evaluations = 0;

    // The strip positions S_i at state y (time t): s_i = S_i - u2_i,ref t is the state, S_i = 0
    // at the start.
    double position(int span, double t, const double* y) const {
        return steady_speed[static_cast<std::size_t>(span)] * t + y[n + span];
    }

    // The thickness transport at (t, y): stand i+1's entry deviation y2_i(t_d) - y2_i,ref and
    // its rate per unit of stand i's current exit speed, y2_i'(t_d) / u2_i(t_d) (the right-hand
    // side multiplies by u2_i(t): dt_d/dt = u2_i(t) / u2_i(t_d), from S_i(t) - S_i(t_d) = L_i).
    bool transport(double t, const double* y) {
        std::fill(deviation.begin(), deviation.end(), 0.0);
        std::fill(rate_per_speed.begin(), rate_per_speed.end(), 0.0);
        for (int i = 0; i < spans; ++i) {
            const Delayed d = history[static_cast<std::size_t>(i)].at(position(i, t, y));
            if (!d.ok || !(d.speed > 0.0)) return false;
            transport_time[static_cast<std::size_t>(i)] = t - d.departure;
            if (frozen) continue;
            deviation[static_cast<std::size_t>(i + 1)] = d.thickness;
            rate_per_speed[static_cast<std::size_t>(i + 1)] = d.rate / d.speed;
        }
        return true;
    }

    DynamicsStatus evaluate(double t, const double* y, double* ydot) {
        if (!transport(t, y)) {
            detail =
                "the thickness transport looked past its history (a step longer than the delay)";
            return DynamicsStatus::solver_failure;
        }
        MillFailure failure;
        const DynamicsStatus status = model->rhs_with_history(
            t, y, deviation.data(), rate_per_speed.data(), ydot, exit_speed.data(), &failure);
        if (status != DynamicsStatus::ok) {
            where = failure;
            return status;
        }
        for (int i = 0; i < spans; ++i)
            ydot[n + i] =
                exit_speed[static_cast<std::size_t>(i)] - steady_speed[static_cast<std::size_t>(i)];
        return DynamicsStatus::ok;
    }

    // After an accepted step at t: the node of every span from the state y and its rate ydot.
    void record(double t, const double* y, const double* ydot) {
        for (int i = 0; i < spans; ++i) {
            const int o = model->displacement_index(i);  // stand i's block: q at o, q' at o + 6
            Node node;
            node.t = t;
            node.position = position(i, t, y);
            node.speed = steady_speed[static_cast<std::size_t>(i)] + ydot[n + i];
            node.thickness = y[o + 2] - y[o + 3];
            node.rate = y[o + 8] - y[o + 9];
            node.acceleration = ydot[o + 8] - ydot[o + 9];
            History& h = history[static_cast<std::size_t>(i)];
            h.append(node);
            h.prune();
        }
    }
};

// A state without a valid right-hand side is recoverable for CVODE (a trial step may overshoot
// into a limit, time_integration.cpp); a history lookup past its end is not.
int right_hand_side(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
    auto* run = static_cast<Run*>(user_data);
    const DynamicsStatus status = run->evaluate(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
    if (status == DynamicsStatus::ok) return 0;
    run->last_failure = status;
    if (run->detail != nullptr) return -1;
    return ++run->limit_failures > limit_failure_budget ? -1 : 1;
}

// The Newton iteration's Jacobian: the mill's A0 at the state (the bite sensitivities,
// docs/model.md §6.1) and the strip positions' rows d u2_i / dz. It leaves out the delayed
// inputs' dependence on the state (y1_{i+1} moves with s_i through t_d, by y2_i'(t_d) / u2_i(t_d)
// per metre) and takes each stand's bite at its steady y1: an approximation Newton tolerates,
// as the rates themselves are exact.
int jacobian(sunrealtype t, N_Vector y, N_Vector, SUNMatrix J, void* user_data, N_Vector, N_Vector,
             N_Vector) {
    auto* run = static_cast<Run*>(user_data);
    const int n = run->n;
    const Eigen::Map<const Eigen::VectorXd> z(N_VGetArrayPointer(y), n);
    MillLinearisation lin = run->model->linearise(z, false);
    if (lin.status != DynamicsStatus::ok) {
        // within a step of a limit: central differences of the frozen mill, no position rows
        const Linearisation fd = finite_difference_jacobian(*run->model, z, t);
        run->fallback_rhs_evaluations += 2 * n;
        if (fd.status != DynamicsStatus::ok) return 1;
        lin.jacobian = fd.jacobian;
        lin.exit_speed = Eigen::MatrixXd::Zero(run->stands, n);
    }
    SUNMatZero(J);
    for (int j = 0; j < n; ++j) {
        sunrealtype* column = SUNDenseMatrix_Column(J, j);
        for (int i = 0; i < n; ++i) column[i] = lin.jacobian(i, j);
        for (int i = 0; i < run->spans; ++i) column[n + i] = lin.exit_speed(i, j);
    }
    return 0;
}

// The model's margins (span forces, y1 - y2 per stand), each stand's y1 moved by the transport.
int limit_margins(sunrealtype t, N_Vector y, sunrealtype* margins, void* user_data) {
    auto* run = static_cast<Run*>(user_data);
    const double* z = N_VGetArrayPointer(y);
    run->model->limit_margins(t, z, margins);
    if (!run->transport(t, z)) return 0;  // a trial past the history: the rhs reports it
    for (int i = 0; i < run->stands; ++i)
        margins[run->span_margins + i] += run->deviation[static_cast<std::size_t>(i)];
    return 0;
}

MillTimeStatus from_dynamics(DynamicsStatus status) {
    switch (status) {
        case DynamicsStatus::ok: return MillTimeStatus::ok;
        case DynamicsStatus::slack_strip: return MillTimeStatus::slack_span;
        case DynamicsStatus::contact_lost: return MillTimeStatus::contact_lost;
        case DynamicsStatus::skidding: return MillTimeStatus::skidding;
        case DynamicsStatus::cancelled: return MillTimeStatus::cancelled;
        case DynamicsStatus::solver_failure: break;
    }
    return MillTimeStatus::solver_failure;
}

// The outputs of state y at time t (the transport already evaluated there by `run.transport`).
// A stand whose bite does not solve at an output (an interpolated state) ends the run there.
BiteStatus sample(const Run& run, double t, const double* y, MillTimeSample& out, int& failed) {
    const MillModel& model = *run.model;
    out.t = t;
    out.stands.resize(static_cast<std::size_t>(run.stands));
    out.span_force.assign(static_cast<std::size_t>(run.stands + 1), 0.0);
    out.transport_time = run.transport_time;
    for (int i = 0; i < run.stands; ++i) {
        const double deviation = run.deviation[static_cast<std::size_t>(i)];
        const BiteState state = model.bite_state(i, y, deviation);
        const BiteResult& bite = model.stand(i).solve_bite(state);
        if (bite.status != BiteStatus::ok) {
            failed = i;
            return bite.status;
        }
        const int o = model.displacement_index(i);
        MillStandSample& s = out.stands[static_cast<std::size_t>(i)];
        s.gap = y[o + 2] - y[o + 3];
        s.force = bite.force;
        s.back_tension = state.back_tension;
        s.front_tension = state.front_tension;
        s.entry_thickness = state.entry_thickness;
        s.exit_thickness = state.exit_thickness;
        s.entry_speed = bite.entry_speed;
        s.exit_speed = bite.exit_speed;
        // the span behind this stand (and, for the last, the one ahead): its force, or the held
        // stress times the thickness it is held on
        const int back = model.back_span(i);
        out.span_force[static_cast<std::size_t>(i)] =
            back >= 0 ? y[back] : state.back_tension * state.entry_thickness;
        if (i + 1 == run.stands) {
            const int front = model.front_span(i);
            out.span_force[static_cast<std::size_t>(i + 1)] =
                front >= 0 ? y[front] : state.front_tension * state.exit_thickness;
        }
    }
    return BiteStatus::ok;
}

}  // namespace

MillTimeResult mill_time_domain(const Mill& mill, const MillSteadyState& steady,
                                const MillKick& kick, const std::vector<double>& output_times,
                                const MillTimeOptions& options, const Control& control) {
    MillTimeResult result;
    if (const char* defect = mill_defect(mill); *defect != '\0') {
        result.message = defect;
        return result;
    }
    if (steady.status != MillSteadyStatus::ok ||
        steady.stands.size() != static_cast<std::size_t>(mill.size())) {
        result.message = "the mill has no steady state to start from";
        result.stand = steady.stand;
        return result;
    }
    for (std::size_t k = 0; k < output_times.size(); ++k) {
        if (!(output_times[k] > (k == 0 ? 0.0 : output_times[k - 1])) ||
            !std::isfinite(output_times[k])) {
            result.message = "the output times must be positive and increasing";
            return result;
        }
    }
    if (kick.stand >= mill.size() || !std::isfinite(kick.gap)) {
        result.message = "the kicked stand is not in the mill";
        return result;
    }
    if (!(options.relative_tolerance > 0.0) || !(options.absolute_tolerance_scale > 0.0) ||
        options.max_step < 0.0 || options.max_total_steps <= 0) {
        result.message = "the integration options must be positive";
        return result;
    }

    const MillModel model(mill, steady);
    if (model.status() != BiteStatus::ok) {
        result.message = "a stand's dynamics bite has no steady state";
        result.stand = model.failed_stand();
        return result;
    }
    const int n = model.size();
    if (kick.state.size() != 0 && kick.state.size() != n) {
        result.message = "the kick's state has not the mill model's size";
        return result;
    }

    Run run;
    run.model = &model;
    run.n = n;
    run.stands = mill.size();
    run.spans = run.stands - 1;
    run.span_margins = model.margin_count() - run.stands;
    run.first_span = mill.entry == MillBoundary::span ? 0 : 1;
    run.frozen = options.frozen_transport;
    run.deviation.assign(static_cast<std::size_t>(run.stands), 0.0);
    run.rate_per_speed.assign(static_cast<std::size_t>(run.stands), 0.0);
    run.exit_speed.assign(static_cast<std::size_t>(run.stands), 0.0);
    run.transport_time.assign(static_cast<std::size_t>(run.spans), 0.0);
    double shortest_delay = std::numeric_limits<double>::infinity();
    for (int i = 0; i < run.spans; ++i) {
        const double u = model.stand(i).reference().bite.exit_speed;
        run.steady_speed.push_back(u);
        run.history.emplace_back(model.span_length(i), u);
        result.delay.push_back(model.span_length(i) / u);
        shortest_delay = std::min(shortest_delay, result.delay.back());
    }
    // a quarter of the shortest delay: the strip entering a stand left the stand before at least
    // three quarters of a step before the last accepted one, inside the history
    double max_step = options.max_step;
    if (run.spans > 0 && !options.frozen_transport)
        max_step = max_step > 0.0 ? std::min(max_step, shortest_delay / 4.0) : shortest_delay / 4.0;
    result.max_step = max_step;

    // the start: z0 kicked, the strip positions at zero
    const int size = n + run.spans;
    Eigen::VectorXd y0 = Eigen::VectorXd::Zero(size);
    y0.head(n) = model.equilibrium();
    if (kick.state.size() == n) y0.head(n) += kick.state;
    if (kick.stand >= 0) {
        const int o = model.displacement_index(kick.stand);
        y0(o + 2) += 0.5 * kick.gap;
        y0(o + 3) -= 0.5 * kick.gap;
    }
    std::vector<double> tolerances(static_cast<std::size_t>(size));
    for (int i = 0; i < size; ++i) {
        // the strip positions like the displacements (a 1e-10 m position is 1e-11 s of delay)
        const double tol = i < n ? model.absolute_tolerance(i) : 1e-10;
        tolerances[static_cast<std::size_t>(i)] = options.absolute_tolerance_scale * tol;
    }

    const auto fail = [&](DynamicsStatus status, const MillFailure& where, double t) {
        result.status = from_dynamics(status);
        result.message = run.detail ? run.detail : cvode::end_message(status);
        result.stand = where.stand;
        result.span = where.span;
        result.end_time = t;
    };

    // the start's node: the rates at the kicked state (a kick into a limit ends the run at 0)
    result.end_time = 0.0;
    Eigen::VectorXd rate0(size);
    if (const DynamicsStatus status = run.evaluate(0.0, y0.data(), rate0.data());
        status != DynamicsStatus::ok) {
        fail(status, run.where, 0.0);
        return result;
    }
    // the kicked state is the strip leaving from now on (the history before it is steady)
    run.record(0.0, y0.data(), rate0.data());

    cvode::Cvode cv;
    result.message = cvode::setup(cv, size, 0.0, y0.data(), tolerances.data(),
                                  options.relative_tolerance, right_hand_side, jacobian, &run);
    if (*result.message != '\0') {
        result.status = MillTimeStatus::solver_failure;
        return result;
    }
    if (CVodeRootInit(cv.memory, model.margin_count(), limit_margins) != CV_SUCCESS) {
        result.status = MillTimeStatus::solver_failure;
        result.message = "CVODE root finding setup failed";
        return result;
    }
    if (max_step > 0.0) CVodeSetMaxStep(cv.memory, max_step);
    if (!output_times.empty()) CVodeSetStopTime(cv.memory, output_times.back());

    result.status = MillTimeStatus::ok;
    result.message = "ok";
    const double end = output_times.empty() ? 0.0 : output_times.back();
    std::size_t next = 0;
    Eigen::VectorXd state(size), rate(size);
    const auto emit = [&](double limit) {
        // every output time up to `limit` (inside the last step: CVODE's interpolant)
        while (next < output_times.size() && output_times[next] <= limit) {
            if (control.should_stop()) {
                result.status = MillTimeStatus::cancelled;
                result.message = "cancelled";
                return false;
            }
            const double tout = output_times[next];
            N_Vector v = N_VMake_Serial(size, state.data(), cv.context);
            const int got = CVodeGetDky(cv.memory, tout, 0, v);
            N_VDestroy(v);
            MillTimeSample s;
            int failed = -1;
            if (got != CV_SUCCESS || !run.transport(tout, state.data())) {
                result.status = MillTimeStatus::solver_failure;
                result.message = "the output could not be interpolated";
                return false;
            }
            const BiteStatus bite = sample(run, tout, state.data(), s, failed);
            if (bite != BiteStatus::ok) {
                fail(from_bite(bite), MillFailure{failed, -1}, tout);
                return false;
            }
            result.samples.push_back(std::move(s));
            result.end_time = tout;
            control.report(tout / end);
            ++next;
        }
        return true;
    };

    double* y = N_VGetArrayPointer(cv.y);
    while (next < output_times.size()) {
        sunrealtype t = 0.0;
        const int flag = CVode(cv.memory, end, cv.y, &t, CV_ONE_STEP);
        if (flag < 0) {
            if (run.last_failure != DynamicsStatus::ok) fail(run.last_failure, run.where, t);
            else {
                result.status = MillTimeStatus::solver_failure;
                result.message = "CVODE could not continue (step size too small)";
                result.end_time = t;
            }
            break;
        }
        if (flag == CV_ROOT_RETURN) {
            // y is the state at the root, inside the last step: the outputs before it first
            if (!emit(t)) break;
            std::vector<int> crossed(static_cast<std::size_t>(model.margin_count()), 0);
            CVodeGetRootInfo(cv.memory, crossed.data());
            int limit = -1;
            for (int i = 0; i < model.margin_count(); ++i)
                if (crossed[static_cast<std::size_t>(i)] < 0) limit = i;  // crossed downwards
            if (limit >= 0) {
                MillFailure where;
                if (limit < run.span_margins) where.span = run.first_span + limit;
                else where.stand = limit - run.span_margins;
                run.detail = nullptr;
                fail(model.margin_status(limit), where, t);
                break;
            }
            continue;  // an upward crossing (a tension recovering) is no limit
        }
        // an accepted step at t: its node, then the outputs it passed
        N_Vector d = N_VMake_Serial(size, rate.data(), cv.context);
        CVodeGetDky(cv.memory, t, 1, d);
        N_VDestroy(d);
        run.record(t, y, rate.data());
        if (!emit(t)) break;
        long steps = 0;
        CVodeGetNumSteps(cv.memory, &steps);
        if (steps > options.max_total_steps) {
            result.status = MillTimeStatus::step_budget;
            result.message = "the step budget of the run is exhausted";
            result.end_time = t;
            break;
        }
    }
    CVodeGetNumSteps(cv.memory, &result.steps);
    CVodeGetNumRhsEvals(cv.memory, &result.rhs_evaluations);
    CVodeGetNumJacEvals(cv.memory, &result.jacobian_evaluations);
    return result;
}

}  // namespace rollgap::core
