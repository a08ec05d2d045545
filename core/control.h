#pragma once
// How a caller steers a long computation from outside: cancel it (a deadline, a deleted job)
// and hear how far it got. Both are optional; core never blocks on them.

#include <functional>

#include "core/parallel_for.h"

namespace rollgap::core {

struct Control {
    std::function<bool()> cancelled;       // polled between units of work
    std::function<void(double)> progress;  // fraction done, 0..1
    // The most threads one computation may spread over (the scan speeds of a critical-speed
    // search, the points of a sweep); 0: the machine's cores. Results do not depend on it.
    int threads = 0;

    bool should_stop() const { return cancelled && cancelled(); }
    int thread_budget() const { return threads > 0 ? threads : default_thread_count(); }
    void report(double fraction) const {
        if (progress) progress(fraction);
    }
};

}  // namespace rollgap::core
