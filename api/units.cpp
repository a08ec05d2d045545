#include "api/units.h"

#include <array>
#include <charconv>
#include <cmath>
#include <string>

#include "api/text.h"

namespace rollgap::api {
namespace {

// (shortest decimal form of value) × 10^shift, correctly rounded to a double.
double shift_decimal_exponent(double value, int shift) {
    if (!std::isfinite(value) || value == 0.0 || shift == 0) return value;
    std::array<char, 64> text{};
    // Shortest round-trip digits in scientific form, e.g. "1.6e-03".
    const auto written =
        std::to_chars(text.data(), text.data() + text.size(), value, std::chars_format::scientific);
    const std::string_view shortest(text.data(),
                                    static_cast<std::size_t>(written.ptr - text.data()));
    const std::size_t exponent_mark = shortest.find('e');
    int exponent = 0;
    std::from_chars(
        shortest.data() + exponent_mark + 1 + (shortest[exponent_mark + 1] == '+' ? 1 : 0),
        shortest.data() + shortest.size(), exponent);
    const std::string shifted =
        concat(shortest.substr(0, exponent_mark), "e", std::to_string(exponent + shift));
    double result = 0.0;
    const auto parsed = std::from_chars(shifted.data(), shifted.data() + shifted.size(), result);
    if (parsed.ec == std::errc::result_out_of_range) {
        // Beyond the double range (bounds keep client values far from it): overflow to ±inf,
        // underflow to 0, as the arithmetic would.
        return value * std::pow(10.0, shift);
    }
    return result;
}

}  // namespace

double to_si(double value, Unit unit) { return shift_decimal_exponent(value, unit.si_exponent); }

double from_si(double si_value, Unit unit) {
    return shift_decimal_exponent(si_value, -unit.si_exponent);
}

std::string format_number(double value) {
    std::array<char, 400> text{};
    const double magnitude = std::fabs(value);
    const bool everyday = magnitude == 0.0 || (magnitude >= 1e-6 && magnitude < 1e15);
    const auto written =
        std::to_chars(text.data(), text.data() + text.size(), value,
                      everyday ? std::chars_format::fixed : std::chars_format::scientific);
    return std::string(text.data(), written.ptr);
}

}  // namespace rollgap::api
