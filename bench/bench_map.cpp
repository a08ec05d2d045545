// Timing of a stability map (docs/model.md, "Stability maps"): the critical speed over a 20 × 20
// grid of the default scenario, reduction 0.10-0.30 × entry thickness 1.0-2.0 mm, default search
// (1-60 m/s, 0.5 m/s steps), on a pool of 2 threads. One run: the map takes tens of seconds.
//
// Output, one figure per line on stdout (as bench_model):
//     map.20x20.<figure>: <value> <unit>
// Usage: bench_map [--threads N]

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/map.h"
#include "service/worker_pool.h"

int main(int argc, char** argv) {
    int threads = 2;
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--threads") == 0) threads = std::atoi(argv[i + 1]);
    }
    constexpr int n = 20;
    std::vector<rollgap::core::Scenario> cells;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            rollgap::core::Scenario s;
            s.strip.reduction = 0.10 + 0.20 * i / (n - 1);
            s.strip.entry_thickness = 1.0e-3 + 1.0e-3 * j / (n - 1);
            cells.push_back(s);
        }
    }
    // CPU time beside the wall time: on a shared machine the wall time measures the neighbours too
    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    const auto pool = rollgap::service::local_pool(static_cast<std::size_t>(std::max(1, threads)));
    rollgap::core::Control control;
    control.executor = pool.get();
    const rollgap::core::StabilityMap map = rollgap::core::stability_map(cells, n, n, {}, control);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    int found = 0;
    for (const auto& cell : map.cells)
        found += cell.status == rollgap::core::CriticalSpeedStatus::found;
    std::printf("map.20x20.threads: %d\n", threads);
    std::printf("map.20x20.wall: %.3f s\n", seconds);
    std::printf("map.20x20.per_cell: %.3f ms\n", 1e3 * seconds / (n * n));
    std::printf("map.20x20.cpu: %.3f s\n", cpu_seconds);
    std::printf("map.20x20.found: %d cells\n", found);
    std::printf("map.20x20.type_changes: %zu pairs\n", map.changes.size());
    return found > 0 ? 0 : 1;
}
