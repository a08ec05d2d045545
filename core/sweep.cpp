#include "core/sweep.h"

#include <atomic>

#include "core/parallel_for.h"

namespace rollgap::core {

namespace {

template <class Result, class Analysis>
std::vector<Result> sweep(std::span<const Scenario> scenarios, const Control& control,
                          Analysis&& analysis) {
    // A point the sweep never reached because it was cancelled says so.
    Result not_run;
    not_run.status = decltype(not_run.status)::cancelled;
    std::vector<Result> results(scenarios.size(), not_run);
    std::atomic<int> done{0};
    const int n = static_cast<int>(scenarios.size());
    parallel_for(n, control, [&](int i) {
        if (control.should_stop()) return;
        results[static_cast<std::size_t>(i)] = analysis(scenarios[static_cast<std::size_t>(i)]);
        control.report(static_cast<double>(++done) / n);
    });
    return results;
}

}  // namespace

std::vector<CriticalSpeedResult> sweep_critical_speed(std::span<const Scenario> scenarios,
                                                      const CriticalSpeedOptions& options,
                                                      const Control& control, bool keep_scan) {
    // The parallelism is across the sweep: each point's own scan runs on its thread.
    const Control inner = control.nested(1);
    // Without the scans kept, each point's search may stop at its first crossing (§7.3).
    CriticalSpeedOptions search = options;
    if (!keep_scan) search.stop_at_crossing = true;
    return sweep<CriticalSpeedResult>(scenarios, control, [&](const Scenario& s) {
        CriticalSpeedResult result = critical_speed(s, search, inner);
        if (!keep_scan) {
            result.scan = {};
            result.branches = {};
        }
        return result;
    });
}

std::vector<AmplitudeResult> sweep_amplitude(std::span<const Scenario> scenarios,
                                             const AmplitudeOptions& options,
                                             const Control& control) {
    const Control inner = control.nested(1);
    return sweep<AmplitudeResult>(scenarios, control, [&](const Scenario& s) {
        return vibration_amplitude(s, options, inner);
    });
}

std::optional<ChatterType> crossing_chatter_type(const CriticalSpeedResult& result) {
    if (result.status != CriticalSpeedStatus::found &&
        result.status != CriticalSpeedStatus::unstable_at_lower_bound) {
        return std::nullopt;
    }
    return result.unstable_mode.chatter.type;
}

std::vector<ChatterTypeChange> chatter_type_changes(
    const std::vector<std::optional<ChatterType>>& crossing_types,
    const std::vector<std::pair<int, int>>& neighbours) {
    std::vector<ChatterTypeChange> changes;
    const int n = static_cast<int>(crossing_types.size());
    for (const auto& [a, b] : neighbours) {
        if (a < 0 || b < 0 || a >= n || b >= n) continue;
        const auto& from = crossing_types[static_cast<std::size_t>(a)];
        const auto& to = crossing_types[static_cast<std::size_t>(b)];
        if (from && to && *from != *to) changes.push_back({a, b, *from, *to});
    }
    return changes;
}

std::vector<ChatterTypeChange> chatter_type_changes(
    const std::vector<CriticalSpeedResult>& results,
    const std::vector<std::pair<int, int>>& neighbours) {
    std::vector<std::optional<ChatterType>> types;
    types.reserve(results.size());
    for (const CriticalSpeedResult& result : results)
        types.push_back(crossing_chatter_type(result));
    return chatter_type_changes(types, neighbours);
}

std::vector<std::pair<int, int>> sequence_neighbours(int count) {
    std::vector<std::pair<int, int>> neighbours;
    for (int i = 0; i + 1 < count; ++i) neighbours.emplace_back(i, i + 1);
    return neighbours;
}

std::vector<ChatterTypeChange> chatter_type_changes(
    const std::vector<CriticalSpeedResult>& results) {
    return chatter_type_changes(results, sequence_neighbours(static_cast<int>(results.size())));
}

}  // namespace rollgap::core
