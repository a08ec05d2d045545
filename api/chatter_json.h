#pragma once
// Where the crossing mode of a sweep or a map changes its chatter type (docs/model.md,
// "Chatter type"), as JSON.

#include <functional>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/sweep.h"

namespace rollgap::api {

// [{"from", "to", "from_chatter_type", "to_chatter_type"}], "from" and "to" as `point` writes
// the index of a result (a sweep: its value; a map: its pair of values).
// The JSON Schema of a chatter type ("third_octave", "fifth_octave" or "other") and the
// descriptions of a mode's two type members.
nlohmann::json chatter_type_schema(bool nullable = false);
inline constexpr std::string_view chatter_type_text =
    "The chatter type from the mode shape (docs/model.md, \"Chatter type\"): `third_octave`, the roll "
    "packages move against each other and the gap breathes; `fifth_octave`, the work rolls vibrate against "
    "their back-up rolls; `other`, the mode hardly changes the gap.";
inline constexpr std::string_view chatter_band_text =
    "The chatter type the mode's frequency alone suggests (third octave 100-300 Hz, fifth octave 500-700 Hz), "
    "beside chatter_type as a check.";

// The JSON Schema of the changes, "from" and "to" of `point_schema`.
nlohmann::json chatter_type_changes_schema(const nlohmann::json& point_schema);

nlohmann::json chatter_type_changes_json(const std::vector<core::ChatterTypeChange>& changes,
                                         const std::function<nlohmann::json(int)>& point);

// The same from points as written (sweep points, map cells): each document's "chatter_type" is
// the crossing mode's type, null exactly where the point has none (crossing_members), so the
// changes follow from the documents alone, whichever process computed each point.
nlohmann::json chatter_type_changes_json(const nlohmann::json& point_documents,
                                         const std::vector<std::pair<int, int>>& neighbours,
                                         const std::function<nlohmann::json(int)>& point);

}  // namespace rollgap::api
