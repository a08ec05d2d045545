#include "api/chatter_json.h"

#include "api/result_table.h"

namespace rollgap::api {

nlohmann::json chatter_type_schema(bool nullable) {
    return enum_schema({"third_octave", "fifth_octave", "other"}, nullable);
}

nlohmann::json chatter_type_changes_schema(const nlohmann::json& point_schema) {
    nlohmann::json from = point_schema, to = point_schema;
    from["description"] = "The point before the change.";
    to["description"] = "The point after it.";
    nlohmann::json from_type = chatter_type_schema(), to_type = chatter_type_schema();
    from_type["description"] = "The chatter type of the crossing mode at `from`.";
    to_type["description"] = "The chatter type of the crossing mode at `to`.";
    return array_schema(
        object_schema("A pair of neighbouring points whose crossing modes differ in chatter type.",
                      {{"from", from},
                       {"to", to},
                       {"from_chatter_type", from_type},
                       {"to_chatter_type", to_type}},
                      {"from", "to", "from_chatter_type", "to_chatter_type"}));
}

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
