#pragma once
// "did you mean ...?" for unknown field names: a mistyped unit suffix ("entry_thickness_m"
// for "entry_thickness_mm") is the error the unit-in-every-name schema exists to catch, so the
// message should point at the intended field.

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace rollgap::api {

// The known name closest to `name` in edit distance, if it is close enough to be a typo
// or a wrong unit suffix rather than an unrelated word.
std::optional<std::string_view> closest_name(std::string_view name,
                                             std::span<const std::string_view> known);

// "; did you mean 'suggestion'?" to append to a message, or "" without a suggestion: every
// message that suggests a name words it the same way.
std::string did_you_mean(std::optional<std::string_view> suggestion);
// The same with the closest known name to `name` (closest_name).
std::string did_you_mean(std::string_view name, std::span<const std::string_view> known);

}  // namespace rollgap::api
