#include "api/chatter_json.h"

#include <array>
#include <optional>
#include <string>

#include "api/result_table.h"

namespace rollgap::api {
namespace {

// A written chatter type back to core's; nothing for null (or anything that is not a type).
std::optional<core::ChatterType> written_chatter_type(const nlohmann::json& value) {
    if (!value.is_string()) return std::nullopt;
    for (const core::ChatterType type :
         std::array{core::ChatterType::third_octave, core::ChatterType::fifth_octave,
                    core::ChatterType::other}) {
        if (value.get_ref<const std::string&>() == core::to_string(type)) return type;
    }
    return std::nullopt;
}

}  // namespace

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

nlohmann::json chatter_type_changes_json(const nlohmann::json& point_documents,
                                         const std::vector<std::pair<int, int>>& neighbours,
                                         const std::function<nlohmann::json(int)>& point) {
    std::vector<std::optional<core::ChatterType>> types;
    types.reserve(point_documents.size());
    for (const nlohmann::json& document : point_documents) {
        const auto found = document.find("chatter_type");
        types.push_back(found != document.end() ? written_chatter_type(*found) : std::nullopt);
    }
    return chatter_type_changes_json(core::chatter_type_changes(types, neighbours), point);
}

}  // namespace rollgap::api
