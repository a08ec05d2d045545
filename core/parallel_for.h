#pragma once
// Runs body(i) for i in [0, n) on up to `threads` threads. Each index is independent and writes
// only its own output, so results do not depend on the thread count.

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace rollgap::core {

inline int default_thread_count() { return std::max(1u, std::thread::hardware_concurrency()); }

template <class Body>
void parallel_for(int n, int threads, Body&& body) {
    threads = std::clamp(threads, 1, std::max(1, n));
    if (threads == 1) {
        for (int i = 0; i < n; ++i) body(i);
        return;
    }
    std::atomic<int> next{0};
    auto worker = [&] {
        for (int i = next++; i < n; i = next++) body(i);
    };
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(threads - 1));
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();
}

}  // namespace rollgap::core
