#pragma once
// Where the crossing mode of a sweep or a map changes its chatter type (docs/model.md,
// "Chatter type"), as JSON.

#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/sweep.h"

namespace rollgap::api {

// [{"from", "to", "from_chatter_type", "to_chatter_type"}], "from" and "to" as `point` writes
// the index of a result (a sweep: its value; a map: its pair of values).
nlohmann::json chatter_type_changes_json(const std::vector<core::ChatterTypeChange>& changes,
                                         const std::function<nlohmann::json(int)>& point);

}  // namespace rollgap::api
