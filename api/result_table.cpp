#include "api/result_table.h"

#include "api/text.h"

namespace rollgap::api {
namespace {

nlohmann::json type(std::string_view name, bool nullable) {
    return nullable ? nlohmann::json::array({name, "null"}) : nlohmann::json(name);
}

}  // namespace

nlohmann::json number_schema(Unit unit, bool nullable) {
    return {{"type", type("number", nullable)}, {"x-unit", unit.code}};
}

nlohmann::json integer_schema(bool nullable) { return {{"type", type("integer", nullable)}}; }

nlohmann::json boolean_schema(bool nullable) { return {{"type", type("boolean", nullable)}}; }

nlohmann::json string_schema() { return {{"type", "string"}}; }

nlohmann::json enum_schema(std::initializer_list<std::string_view> choices, bool nullable) {
    nlohmann::json values = nlohmann::json::array();
    for (const std::string_view choice : choices) values.push_back(choice);
    if (nullable) values.push_back(nullptr);
    return {{"enum", std::move(values)}};
}

nlohmann::json ref_schema(std::string_view component, bool nullable) {
    nlohmann::json ref = {{"$ref", concat("#/components/schemas/", component)}};
    if (!nullable) return ref;
    return {{"oneOf", nlohmann::json::array({std::move(ref), {{"type", "null"}}})}};
}

nlohmann::json array_schema(nlohmann::json items) {
    return {{"type", "array"}, {"items", std::move(items)}};
}

nlohmann::json object_schema(
    std::string_view description,
    const std::vector<std::pair<std::string_view, nlohmann::json>>& properties,
    const std::vector<std::string_view>& required) {
    nlohmann::json members = nlohmann::json::object();
    for (const auto& [name, schema] : properties) {
        nlohmann::json property = schema;
        // The unit is in the name; the description says it in words too.
        const nlohmann::json* unit =
            property.contains("x-unit") ? &property["x-unit"]
            : property.contains("items") && property["items"].contains("x-unit")
                ? &property["items"]["x-unit"]
                : nullptr;
        if (unit != nullptr) {
            const std::string code = unit->get<std::string>();
            property["description"] =
                concat(property.value("description", std::string()),
                       code == "1" ? " Dimensionless." : concat(" Unit: ", code, "."));
        }
        members[std::string(name)] = std::move(property);
    }
    nlohmann::json names = nlohmann::json::array();
    for (const std::string_view name : required) names.push_back(name);
    return {
        {"type", "object"},
        {"description", description},
        {"properties", std::move(members)},
        {"required", std::move(names)},
        {"additionalProperties", false},
    };
}

}  // namespace rollgap::api
