#include "core/amplitude.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/stability.h"
#include "core/time_integration.h"

namespace rollgap::core {

const char* to_string(AmplitudeStatus status) {
    switch (status) {
        case AmplitudeStatus::settled: return "settled";
        case AmplitudeStatus::growing: return "growing";
        case AmplitudeStatus::decaying: return "decaying";
        case AmplitudeStatus::limit_reached: return "limit_reached";
        case AmplitudeStatus::no_steady_state: return "no_steady_state";
        case AmplitudeStatus::cancelled: return "cancelled";
        case AmplitudeStatus::solver_failure: return "solver_failure";
    }
    return "unknown";
}

namespace {

struct Range {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    void add(double v) {
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    double half_span() const { return hi >= lo ? 0.5 * (hi - lo) : 0.0; }
};

}  // namespace

AmplitudeResult vibration_amplitude(const Scenario& s, const AmplitudeOptions& options,
                                    const Control& control) {
    AmplitudeResult out;
    out.speed = s.rolls.speed;

    const SpeedStability linear = stability_at(s);
    out.steady_status = linear.steady_status;
    if (linear.steady_status != BiteStatus::ok) {
        out.message = "no steady state at this speed: the bite skids or loses contact";
        return out;
    }
    out.least_damped_growth_rate = linear.least_damped.eigenvalue.real();
    out.excitation_frequency_Hz = options.excitation_frequency_Hz > 0.0
                                      ? options.excitation_frequency_Hz
                                      : linear.least_damped.frequency_Hz;

    const Scenario dynamics = dynamics_scenario(s);
    const ReferenceState ref = reference_state(dynamics, false);
    const CoupledModel model(dynamics, ref,
                             Excitation{options.excitation_amplitude, out.excitation_frequency_Hz});

    // Sample fast enough for the excitation and for the stack's modes (~400 Hz at the defaults),
    // within a memory budget; a stack too fast to resolve in the window is refused, not run.
    double fastest = std::max(out.excitation_frequency_Hz, 400.0);
    for (const Eigenmode& mode : linear.oscillatory) fastest = std::max(fastest, mode.frequency_Hz);
    constexpr double max_samples = 400'000;
    const double per_period =
        std::min(options.samples_per_period, max_samples / (fastest * options.window));
    if (per_period < 8.0) {
        out.status = AmplitudeStatus::solver_failure;
        out.message =
            "the stack's fastest mode is too fast to resolve in this window: shorten the window";
        return out;
    }
    const double dt = 1.0 / (per_period * fastest);
    const int samples = std::max(10, static_cast<int>(std::ceil(options.window / dt)));
    std::vector<double> times(static_cast<std::size_t>(samples));
    for (int i = 0; i < samples; ++i)
        times[static_cast<std::size_t>(i)] = options.window * (i + 1) / samples;

    constexpr int window_count = 10;
    std::vector<Range> upper(window_count), gap(window_count), force(window_count);
    const Matrix6& M = model.structure().mass;
    const Matrix6& C = model.structure().damping;
    const Matrix6& K = model.structure().structural_stiffness;
    // every stride-th sample, rounded up so the series never holds more than time_series_points
    const int points = std::max(1, options.time_series_points);
    const int stride = options.time_series ? std::max(1, (samples + points - 1) / points) : 0;
    int index = 0;

    auto on_output = [&](const Sample& sample) {
        const int w =
            std::min(window_count - 1, static_cast<int>(sample.t / options.window * window_count));
        const double x3 = sample.z(2), g = sample.z(2) - sample.z(3);
        // b dP = M q'' + C q' + K_s q (eq. 37 with k4 cancelled): the force on the upper work roll
        const Vector6 q = sample.z.head<6>(), qdot = sample.z.segment<6>(6),
                      qddot = sample.zdot.segment<6>(6);
        const double force_change = (M * qddot + C * qdot + K * q)(2);
        upper[static_cast<std::size_t>(w)].add(x3);
        gap[static_cast<std::size_t>(w)].add(g);
        force[static_cast<std::size_t>(w)].add(force_change);
        if (stride > 0 && index % stride == 0) {
            out.t.push_back(sample.t);
            out.x3.push_back(x3);
            out.g.push_back(g);
            out.force_change.push_back(force_change);
        }
        ++index;
        if (index % 256 == 0) control.report(sample.t / options.window);
    };

    Eigen::VectorXd z = model.equilibrium();
    IntegrationOptions integration;
    integration.relative_tolerance = options.relative_tolerance;
    integration.max_step = 0.25 / fastest;
    const IntegrationResult run = integrate(model, z, 0.0, times, on_output, integration, control);
    out.end_status = run.status;
    out.end_time = run.end_time;
    out.steps = run.steps;
    out.rhs_evaluations = run.rhs_evaluations;
    out.jacobian_evaluations = run.jacobian_evaluations;
    out.jacobian_rhs_evaluations = run.jacobian_rhs_evaluations;

    for (int w = 0; w < window_count; ++w) {
        out.windows.push_back({options.window * w / window_count,
                               options.window * (w + 1) / window_count,
                               upper[static_cast<std::size_t>(w)].half_span()});
    }

    // Amplitudes from the last 10 % window that has samples: the last one of the window, or, when
    // a limit ended the run early, the (partial) one in which it ended. Settling and growth from
    // the last two complete windows.
    const double window_length = options.window / window_count;
    const int complete =
        std::min(window_count, static_cast<int>(std::floor(run.end_time / window_length + 1e-9)));
    const int with_data = std::min(
        window_count - 1, static_cast<int>(std::floor(run.end_time / window_length - 1e-9)));
    if (with_data >= 0) {
        const std::size_t last = static_cast<std::size_t>(with_data);
        out.upper_roll = upper[last].half_span();
        out.gap = gap[last].half_span();
        out.force = force[last].half_span();
    }
    if (complete >= 2) {
        const double a1 = upper[static_cast<std::size_t>(complete - 2)].half_span();
        const double a2 = upper[static_cast<std::size_t>(complete - 1)].half_span();
        out.settled =
            run.status == DynamicsStatus::ok && a1 > 0.0 && std::abs(a2 - a1) <= 0.01 * a1;
        out.growth_rate = (a1 > 0.0 && a2 > 0.0) ? std::log(a2 / a1) / window_length : 0.0;
    }

    switch (run.status) {
        case DynamicsStatus::ok:
            out.status = out.settled             ? AmplitudeStatus::settled
                         : out.growth_rate > 0.0 ? AmplitudeStatus::growing
                                                 : AmplitudeStatus::decaying;
            out.message = out.settled ? "the response settled (last two 10 % windows within 1 %)"
                          : out.growth_rate > 0.0
                              ? "the response is still growing at the end of the window"
                              : "the response is still decaying at the end of the window";
            break;
        case DynamicsStatus::cancelled:
            out.status = AmplitudeStatus::cancelled;
            out.message = "cancelled";
            break;
        case DynamicsStatus::contact_lost:
        case DynamicsStatus::skidding:
        case DynamicsStatus::slack_strip:
            out.status = AmplitudeStatus::limit_reached;
            out.message = run.status == DynamicsStatus::contact_lost
                              ? "the vibration opened the gap: contact lost"
                          : run.status == DynamicsStatus::skidding
                              ? "the vibration made the rolls skid"
                              : "the vibration slackened the strip";
            break;
        case DynamicsStatus::solver_failure:
            out.status = AmplitudeStatus::solver_failure;
            out.message = run.message;
            break;
    }
    control.report(1.0);
    return out;
}

}  // namespace rollgap::core
