#include "core/sweep.h"

#include <atomic>

#include "core/parallel_for.h"

namespace rollgap::core {

namespace {

template <class Result, class Analysis>
std::vector<Result> sweep(const std::vector<Scenario>& scenarios, int threads, const Control& control,
                          Analysis&& analysis) {
    // A point the sweep never reached because it was cancelled says so.
    Result not_run;
    not_run.status = decltype(not_run.status)::cancelled;
    std::vector<Result> results(scenarios.size(), not_run);
    std::atomic<int> done{0};
    const int n = static_cast<int>(scenarios.size());
    parallel_for(n, threads, [&](int i) {
        if (control.should_stop()) return;
        results[static_cast<std::size_t>(i)] = analysis(scenarios[static_cast<std::size_t>(i)]);
        control.report(static_cast<double>(++done) / n);
    });
    return results;
}

}  // namespace

std::vector<CriticalSpeedResult> sweep_critical_speed(const std::vector<Scenario>& scenarios,
                                                      const CriticalSpeedOptions& options, int threads,
                                                      const Control& control) {
    CriticalSpeedOptions serial = options;
    serial.threads = 1;  // the parallelism is across the sweep
    Control inner;
    inner.cancelled = control.cancelled;
    return sweep<CriticalSpeedResult>(scenarios, threads, control,
                                      [&](const Scenario& s) { return critical_speed(s, serial, inner); });
}

std::vector<AmplitudeResult> sweep_amplitude(const std::vector<Scenario>& scenarios, const AmplitudeOptions& options,
                                             int threads, const Control& control) {
    Control inner;
    inner.cancelled = control.cancelled;
    return sweep<AmplitudeResult>(scenarios, threads, control,
                                  [&](const Scenario& s) { return vibration_amplitude(s, options, inner); });
}

}  // namespace rollgap::core
