// What splitting a sweep into chunks costs (service/chunked.h): a 20-point critical-speed sweep
// of the default scenario (viscosity 3e-4 to 8e-4 Pa s, default search) evaluated whole and as
// chunks of 1 and 5 points, each chunk's documents passed through text as the job store keeps
// them, then assembled. Every chunk validates and prepares the whole request again, so that
// fixed cost is timed too (evaluate_points of an empty range), up to the largest requests (a
// 1000-value sweep, a 49 × 49 map). One thread, CPU time beside the wall
// time (the least of three runs): on a shared machine the wall time measures the neighbours too.
//
// Output, one figure per line on stdout (as bench_model):
//     chunked.<figure>: <value> <unit>
// Usage: bench_chunked

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <functional>
#include <string>

#include <nlohmann/json.hpp>

#include "service/chunked.h"
#include "service/evaluate.h"

namespace {

using nlohmann::json;
using rollgap::service::Outcome;

struct Timing {
    double wall = 0.0, cpu = 0.0;  // seconds
};

Timing timed(const std::function<void()>& run) {
    const std::clock_t cpu_start = std::clock();
    const auto start = std::chrono::steady_clock::now();
    run();
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
            static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC};
}

json sweep(int count) {
    return {{"analysis", "sweep"},
            {"options",
             {{"parameter", "/lubricant/viscosity_Pa_s"},
              {"range", {{"from", 3e-4}, {"to", 8e-4}, {"count", count}}}}}};
}

json map(int count) {
    const auto axis = [count](const char* parameter, double from, double to) {
        return json{{"parameter", parameter},
                    {"range", {{"from", from}, {"to", to}, {"count", count}}}};
    };
    return {{"analysis", "map"},
            {"options",
             {{"parameters",
               {axis("/strip/reduction", 0.1, 0.3), axis("/lubricant/viscosity_Pa_s", 3e-4, 8e-4)}},
              {"critical_speed", {{"speed_step_m_per_s", 0.5}, {"speed_min_m_per_s", 11}}}}}};
}

// The whole sweep in chunks of `size`, through text, assembled; the dump of the answer.
std::string chunked(const json& request, std::int64_t total, std::int64_t size,
                    const rollgap::core::Control& control) {
    json points = json::array();
    for (std::int64_t begin = 0; begin < total; begin += size) {
        const Outcome chunk = rollgap::service::evaluate_points(
            request, begin, begin + size < total ? begin + size : total, control);
        if (!chunk.ok()) std::fprintf(stderr, "%s\n", chunk.body.dump().c_str());
        for (json& point : json::parse(chunk.body.dump())) points.push_back(std::move(point));
    }
    return rollgap::service::assemble_points(request, points).body.dump();
}

void print(const std::string& name, const Timing& t) {
    std::printf("chunked.%s.wall: %.4f s\n", name.c_str(), t.wall);
    std::printf("chunked.%s.cpu: %.4f s\n", name.c_str(), t.cpu);
}

}  // namespace

int main() {
    rollgap::core::Control one_thread;
    one_thread.threads = 1;
    const json request = sweep(20);
    (void)rollgap::service::evaluate(sweep(2), one_thread);  // the tables' first use
    // Each variant three times, interleaved, the least CPU time kept: the neighbours on a shared
    // machine only ever add time.
    std::string whole;
    const std::int64_t sizes[] = {20, 1, 5};  // 20: evaluate() itself, not chunked
    Timing best[3];
    bool identical = true;
    for (int round = 0; round < 3; ++round) {
        for (int k = 0; k < 3; ++k) {
            std::string answer;
            const Timing t = timed([&] {
                answer = k == 0 ? rollgap::service::evaluate(request, one_thread).body.dump()
                                : chunked(request, 20, sizes[k], one_thread);
            });
            if (k == 0) whole = answer;
            identical = identical && answer == whole;
            if (round == 0 || t.cpu < best[k].cpu) best[k] = t;
        }
    }
    print("sweep20.whole", best[0]);
    for (int k = 1; k < 3; ++k) {
        const std::string name = "sweep20.chunks_of_" + std::to_string(sizes[k]);
        print(name, best[k]);
        std::printf("chunked.%s.cpu_overhead: %.1f %%\n", name.c_str(),
                    100.0 * (best[k].cpu - best[0].cpu) / best[0].cpu);
    }
    std::printf("chunked.sweep20.identical: %s\n", identical ? "yes" : "NO");

    // The fixed cost of one chunk (validating and preparing the whole request), up to the largest
    // requests.
    for (const auto& [name, large] :
         {std::pair{"sweep20", sweep(20)}, std::pair{"sweep1000", sweep(1000)},
          std::pair{"map49x49", map(49)}}) {
        const auto total = rollgap::service::chunkable_points(large);
        if (!total) {
            std::fprintf(stderr, "%s is not chunkable: %s\n", name,
                         rollgap::service::evaluate_points(large, 0, 0).body.dump().c_str());
            return 1;
        }
        constexpr int repeats = 5;
        const json& request_of_size = large;
        const Timing prepare = timed([&] {
            // clang 14 captures no structured binding: a named reference
            for (int i = 0; i < repeats; ++i)
                (void)rollgap::service::evaluate_points(request_of_size, 0, 0);
        });
        std::printf("chunked.%s.points: %lld\n", name, static_cast<long long>(*total));
        std::printf("chunked.%s.prepare_per_chunk.cpu: %.2f ms\n", name,
                    1e3 * prepare.cpu / repeats);
    }
    return identical ? 0 : 1;
}
