#pragma once
// Option member names that more than one analysis reads (its own names stay in its file):
// written once, so two analyses cannot spell the same option two ways.

#include <string_view>

namespace rollgap::api {

inline constexpr std::string_view critical_speed_name = "critical_speed";
inline constexpr std::string_view amplitude_name = "amplitude";
inline constexpr std::string_view tolerance_name = "relative_tolerance";

}  // namespace rollgap::api
