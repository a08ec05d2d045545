#pragma once
// Compound option members (objects) that more than one analysis reads (its own names stay in its
// file; the scalar options are the rows of api/option_table.h):
// written once, so two analyses cannot spell the same option two ways.

#include <string_view>

namespace rollgap::api {

inline constexpr std::string_view critical_speed_name = "critical_speed";
inline constexpr std::string_view amplitude_name = "amplitude";

}  // namespace rollgap::api
