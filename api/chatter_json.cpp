#include "api/chatter_json.h"

namespace rollgap::api {

nlohmann::json chatter_type_changes_json(const std::vector<core::ChatterTypeChange>& changes,
                                         const std::function<nlohmann::json(int)>& point) {
    nlohmann::json out = nlohmann::json::array();
    for (const core::ChatterTypeChange& change : changes) {
        out.push_back({
            {"from", point(change.from)},
            {"to", point(change.to)},
            {"from_chatter_type", core::to_string(change.from_type)},
            {"to_chatter_type", core::to_string(change.to_type)},
        });
    }
    return out;
}

}  // namespace rollgap::api
