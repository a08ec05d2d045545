#include "api/interval.h"

#include "api/text.h"
#include "api/units.h"

namespace rollgap::api {

bool Interval::contains(double value) const {
    const bool above_min = min_open ? value > min : value >= min;
    const bool below_max = max_open ? value < max : value <= max;
    return above_min && below_max;  // false for NaN
}

std::string Interval::text() const {
    return concat(min_open ? "(" : "[", format_number(min), ", ", format_number(max),
                  max_open ? ")" : "]");
}

}  // namespace rollgap::api
