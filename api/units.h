#pragma once
// Engineering units ⇄ SI. Every JSON field carries its unit in its name; core is plain SI.
// Units are powers of ten of the SI unit, and conversions shift the decimal exponent of the
// value's shortest decimal form: 1.6 mm becomes exactly the double nearest 0.0016 m (what
// core's literal 1.6e-3 is), not 1.6 / 1000 with its rounding error, and back again.

#include <string>
#include <string_view>

namespace rollgap::api {

struct Unit {
    std::string_view code;  // UCUM code (case sensitive): "mm", "MPa", "Pa.s", "/MPa", "1"
    int si_exponent;        // SI value = value in this unit × 10^si_exponent
};

// value × 10^si_exponent, correctly rounded from the shortest decimal form of `value`.
double to_si(double value, Unit unit);

// The inverse. A value with up to 15 significant digits converted to SI and back is the
// same double, so an echoed scenario shows what the client sent and reruns bit-identically.
double from_si(double value_si, Unit unit);

// Shortest text that reads back to the same double, without an exponent for everyday
// magnitudes ("0.05", "100000", "1e-08"), for bounds in messages.
std::string format_number(double value);

namespace units {
inline constexpr Unit one{"1", 0};  // dimensionless
inline constexpr Unit metre{"m", 0};
inline constexpr Unit millimetre{"mm", -3};
inline constexpr Unit micrometre{"um", -6};
inline constexpr Unit metre_per_second{"m/s", 0};
inline constexpr Unit second{"s", 0};
inline constexpr Unit per_second{"/s", 0};
inline constexpr Unit megapascal{"MPa", 6};
inline constexpr Unit gigapascal{"GPa", 9};
inline constexpr Unit pascal_second{"Pa.s", 0};
inline constexpr Unit per_megapascal{"/MPa", -6};
inline constexpr Unit hertz{"Hz", 0};
inline constexpr Unit tonne{"t", 3};
inline constexpr Unit giganewton_per_metre{"GN/m", 9};
inline constexpr Unit meganewton_second_per_metre{"MN.s/m", 6};
inline constexpr Unit kilonewton{"kN", 3};
inline constexpr Unit kilonewton_metre{"kN.m", 3};
inline constexpr Unit radian{"rad", 0};
inline constexpr Unit kilogram_per_cubic_metre{"kg/m3", 0};
inline constexpr Unit kilowatt{"kW", 3};
inline constexpr Unit square_metre_per_second{"m2/s", 0};
inline constexpr Unit kilonewton_per_millimetre{"kN/mm", 6};
inline constexpr Unit micrometre_per_kilonewton{"um/kN", -9};
}  // namespace units

}  // namespace rollgap::api
