#pragma once
// Vibration amplitude (docs/model.md §7.4): the nonlinear coupled model driven by a back-tension
// excitation, integrated in time; amplitudes are half peak-to-peak over the last 10 % of the
// window.

#include <vector>

#include "core/control.h"
#include "core/coupled_model.h"
#include "core/scenario.h"

namespace rollgap::core {

struct AmplitudeOptions {
    double window = 2.0;                   // s
    double excitation_amplitude = 1e6;     // Pa, added to s_b as the bite and inlet see it
    double excitation_frequency_Hz = 0.0;  // 0: the least-damped eigenfrequency at this speed
    double samples_per_period = 40.0;      // of the fastest of the excitation and 400 Hz
    double relative_tolerance = 1e-6;
    bool time_series = false;
    int time_series_points = 2000;  // decimated to at most this many
};

enum class AmplitudeStatus {
    settled,
    growing,
    decaying,
    limit_reached,
    no_steady_state,
    cancelled,
    solver_failure
};
const char* to_string(AmplitudeStatus);

struct AmplitudeWindow {
    double start, end;  // s
    double upper_roll;  // half peak-to-peak of x3, m
};

struct AmplitudeResult {
    AmplitudeStatus status = AmplitudeStatus::no_steady_state;
    const char* message = "";
    BiteStatus steady_status = BiteStatus::solver_failure;
    DynamicsStatus end_status = DynamicsStatus::solver_failure;  // what ended the run
    double speed = 0.0;
    double excitation_frequency_Hz = 0.0;
    double least_damped_growth_rate = 0.0;  // Re lambda of the least-damped mode, 1/s

    double end_time = 0.0;     // s, window length unless a limit ended the run
    double upper_roll = 0.0;   // half peak-to-peak of x3 over the last 10 % (or, when a limit
                               // ended the run, over the 10 % window in which it did), m
    double gap = 0.0;          // of g = x3 - x4, m
    double force = 0.0;        // of P - P_ref, N
    bool settled = false;      // the last two 10 % windows agree within 1 %
    double growth_rate = 0.0;  // 1/s, from the last two 10 % windows
    std::vector<AmplitudeWindow> windows;  // the ten 10 % windows

    // decimated, when asked for
    std::vector<double> t, x3, g, force_change;  // force_change: b dP, N

    long steps = 0;
    long rhs_evaluations = 0;
    long jacobian_evaluations = 0;      // the integrator's Jacobians (docs/model.md §6.1)
    long jacobian_rhs_evaluations = 0;  // right-hand sides those took
};

AmplitudeResult vibration_amplitude(const Scenario& s, const AmplitudeOptions& options = {},
                                    const Control& control = {});

}  // namespace rollgap::core
