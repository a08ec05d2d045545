#pragma once
// "did you mean ...?" for unknown field names: a mistyped unit suffix ("entry_thickness_m"
// for "entry_thickness_mm") is the error the unit-in-every-name schema exists to catch, so the
// message should point at the intended field.

#include <optional>
#include <span>
#include <string_view>

namespace rollgap::api {

// The known name closest to `name` in edit distance, if it is close enough to be a typo
// or a wrong unit suffix rather than an unrelated word.
std::optional<std::string_view> closest_name(std::string_view name,
                                             std::span<const std::string_view> known);

}  // namespace rollgap::api
