// Timing of a batch of coils (docs/http-api.md, "Batches"): 1,000 single-stand speed limits
// of the calibrated stand of examples/speed_limit.json (the README's calibration, its posterior
// carried to each coil's chatter limit: nine critical-speed searches a coil), each coil at its
// own speed (16-20.9 m/s) and back tension (15-21 MPa), through the facade as a job's chunks
// run them, on a pool of 2 threads. The same coils without the posterior (one search a coil),
// and 100 of them with what_to_change (the sensitivities a batch leaves out unless asked); and
// before batches, 100 of the calibrated coils one request at a time.
// CPU time beside the wall time: on a shared machine the wall time measures the neighbours too.
//
// Output, one figure per line on stdout (as bench_model):
//     batch.<case>.<figure>: <value> <unit>
// Usage: bench_batch [--threads N] [--coils N]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"
#include "service/worker_pool.h"

namespace {

using nlohmann::json;

json coils(int count) {
    json items = json::array();
    for (int i = 0; i < count; ++i) {
        items.push_back({{"label", "coil-" + std::to_string(i)},
                         {"scenario",
                          {{"rolls", {{"speed_m_per_s", 16.0 + 0.1 * (i % 50)}}},
                           {"tension", {{"back", {{"stress_MPa", 15.0 + (i % 7)}}}}}}}});
    }
    return items;
}

// One case: the batch evaluated on `threads`, its figures printed; false if an item failed.
bool run_case(const char* name, const json& request, int threads) {
    const auto pool = rollgap::service::local_pool(static_cast<std::size_t>(std::max(1, threads)));
    rollgap::core::Control control;
    control.executor = pool.get();
    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    const rollgap::service::Outcome outcome = rollgap::service::evaluate(request, control);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    if (!outcome.ok()) {
        std::fprintf(stderr, "bench_batch: %s: %s\n", name, outcome.body.dump().c_str());
        return false;
    }
    const json& result = outcome.body["result"];
    const int items = result["items_total"];
    std::printf("batch.%s.coils: %d\n", name, items);
    std::printf("batch.%s.threads: %d\n", name, threads);
    std::printf("batch.%s.wall: %.3f s\n", name, seconds);
    std::printf("batch.%s.per_coil: %.2f ms\n", name, 1e3 * seconds / items);
    std::printf("batch.%s.cpu: %.3f s\n", name, cpu);
    std::printf("batch.%s.failed: %d coils\n", name, result["failed"].get<int>());
    return result["failed"] == 0;
}

}  // namespace

int main(int argc, char** argv) {
    int threads = 2;
    int count = 1000;
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--threads") == 0) threads = std::atoi(argv[i + 1]);
        if (std::strcmp(argv[i], "--coils") == 0) count = std::atoi(argv[i + 1]);
    }
    std::ifstream file(std::string(ROLLGAP_SOURCE_DIR) + "/examples/speed_limit.json");
    const json example = json::parse(file, nullptr, false);
    if (example.is_discarded()) {
        std::fprintf(stderr, "bench_batch: examples/speed_limit.json unreadable\n");
        return 1;
    }
    json batch = {{"analysis", "batch"},
                  {"options",
                   {{"analysis", "speed_limit"},
                    {"scenario", example["scenario"]},
                    {"options", example["options"]},
                    {"items", coils(count)}}}};
    bool ok = run_case("calibrated", batch, threads);

    json plain = batch;
    plain["options"]["options"].erase("posterior");
    ok = run_case("without_posterior", plain, threads) && ok;

    // Before batches: the same coils one request at a time, each with both threads for its own
    // inner parallelism (the differences of its propagation, its scan speeds), as a client
    // looping over POST /v1/speed-limit gets them. A tenth of the coils.
    {
        const int n = std::max(1, count / 10);
        const auto pool =
            rollgap::service::local_pool(static_cast<std::size_t>(std::max(1, threads)));
        rollgap::core::Control control;
        control.executor = pool.get();
        const std::clock_t cpu_start = std::clock();
        const auto start = std::chrono::steady_clock::now();
        int failed = 0;
        for (const json& item : coils(n)) {
            json request = {{"analysis", "speed_limit"},
                            {"scenario", example["scenario"]},
                            {"options", example["options"]}};
            request["scenario"].merge_patch(item["scenario"]);
            request["options"]["what_to_change"] = false;
            failed += rollgap::service::evaluate(request, control).ok() ? 0 : 1;
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
        std::printf("batch.one_by_one.coils: %d\n", n);
        std::printf("batch.one_by_one.threads: %d\n", threads);
        std::printf("batch.one_by_one.wall: %.3f s\n", seconds);
        std::printf("batch.one_by_one.per_coil: %.2f ms\n", 1e3 * seconds / n);
        std::printf("batch.one_by_one.cpu: %.3f s\n", cpu);
        std::printf("batch.one_by_one.failed: %d coils\n", failed);
        ok = ok && failed == 0;
    }

    json asked = batch;
    asked["options"]["items"] = coils(std::max(1, count / 10));
    asked["options"]["options"]["what_to_change"] = true;
    ok = run_case("what_to_change", asked, threads) && ok;
    return ok ? 0 : 1;
}
