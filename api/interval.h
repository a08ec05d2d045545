#pragma once
// The allowed range of a numeric field, in the field's own unit, with open or closed ends.

#include <string>

namespace rollgap::api {

struct Interval {
    double min;
    double max;
    bool min_open = false;  // (min, ... : min itself is not allowed
    bool max_open = false;  // ..., max) : max itself is not allowed

    bool contains(double value) const;
    std::string text() const;  // "[0.05, 20]", "(0, 0.7]"
};

inline Interval closed(double min, double max) { return {min, max, false, false}; }
inline Interval open_closed(double min, double max) { return {min, max, true, false}; }
inline Interval closed_open(double min, double max) { return {min, max, false, true}; }

}  // namespace rollgap::api
