#include "api/merge_patch.h"

namespace rollgap::api {

nlohmann::json merge_patch(nlohmann::json target, const nlohmann::json& patch) {
    if (!patch.is_object()) return patch;  // a non-object patch replaces the target
    if (!target.is_object()) target = nlohmann::json::object();
    for (const auto& [name, value] : patch.items()) {
        if (value.is_null()) {
            target.erase(name);
        } else {
            auto member = target.find(name);
            nlohmann::json merged = merge_patch(member == target.end() ? nlohmann::json() : std::move(*member), value);
            target[name] = std::move(merged);
        }
    }
    return target;
}

}  // namespace rollgap::api
