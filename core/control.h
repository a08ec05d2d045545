#pragma once
// How a caller steers a long computation from outside: cancel it (a deadline, a deleted job)
// and hear how far it got. Both are optional; core never blocks on them.

#include <functional>

namespace rollgap::core {

struct Control {
    std::function<bool()> cancelled;          // polled between units of work
    std::function<void(double)> progress;     // fraction done, 0..1

    bool should_stop() const { return cancelled && cancelled(); }
    void report(double fraction) const {
        if (progress) progress(fraction);
    }
};

}  // namespace rollgap::core
