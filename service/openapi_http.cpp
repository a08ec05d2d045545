#include "service/openapi_http.h"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>

namespace rollgap::service {
namespace openapi_http_detail {

using nlohmann::json;

constexpr std::array<std::string_view, 5> methods{"get", "post", "put", "patch", "delete"};

// What the connection answers on any route (service/http/listener.cpp, request_checks.cpp):
// an unreadable request line or header (400), an Accept that admits none of the route's
// media types (406), a request that does not arrive within the read deadline (408), a
// request line or header block above its bound (414, 431), a Host the service does not serve
// (421).
constexpr std::array<std::pair<std::string_view, std::string_view>, 6> transport{{
    {"400", "BadRequest"},
    {"406", "NotAcceptable"},
    {"408", "RequestTimeout"},
    {"414", "UriTooLong"},
    {"421", "MisdirectedRequest"},
    {"431", "HeaderFieldsTooLarge"},
}};

json ref(std::string_view kind, std::string_view name) {
    return {{"$ref", std::string("#/components/").append(kind).append("/").append(name)}};
}

// The schema a "$ref" names (one level of components), or the schema itself.
const json& resolved(const json& document, const json& schema) {
    if (!schema.contains("$ref")) return schema;
    const std::string target = schema["$ref"];
    constexpr std::string_view prefix = "#/components/schemas/";
    if (target.rfind(prefix, 0) != 0) return schema;
    const json& schemas = document["components"]["schemas"];
    const auto found = schemas.find(target.substr(prefix.size()));
    return found == schemas.end() ? schema : *found;
}

// Whether {} is a valid instance: no member required at the top (the analyses' and the
// stored documents' bodies state their rules as `required`; a oneOf of `required` needs one).
bool accepts_empty_object(const json& document, const json& schema) {
    const json& body = resolved(document, schema);
    if (body.contains("required") && !body["required"].empty()) return false;
    return !body.contains("oneOf") && !body.contains("anyOf");
}

// The schema of a request body (JSON or merge patch), or nullptr.
const json* body_schema(const json& body) {
    const auto content = body.find("content");
    if (content == body.end()) return nullptr;
    for (const char* media : {"application/json", "application/merge-patch+json"}) {
        const auto type = content->find(media);
        if (type != content->end() && type->contains("schema")) return &(*type)["schema"];
    }
    return nullptr;
}

void add_headers(json& response, bool poll_hint) {
    if (response.contains("$ref")) return;  // a component: given its headers there
    response["headers"]["X-Request-Id"] = ref("headers", "X-Request-Id");
    if (poll_hint && !response["headers"].contains("Retry-After"))
        response["headers"]["Retry-After"] = ref("headers", "Retry-After");
}

constexpr std::string_view schema_prefix = "#/components/schemas/";

// The components `node` names by $ref (not following them). In a "properties" map the keys
// are member names, not keywords: only its values are schemas.
void collect_refs(const json& node, std::set<std::string>& out) {
    if (node.is_array()) {
        for (const json& item : node) collect_refs(item, out);
        return;
    }
    if (!node.is_object()) return;
    for (const auto& [key, value] : node.items()) {
        if (key == "$ref" && value.is_string()) {
            const std::string target = value;
            if (target.rfind(schema_prefix, 0) == 0)
                out.insert(target.substr(schema_prefix.size()));
        } else {
            collect_refs(value, out);
        }
    }
}

// The components reachable from `start`, following $refs.
std::set<std::string> closure(const json& schemas, std::set<std::string> start) {
    std::set<std::string> seen;
    while (!start.empty()) {
        const std::string name = *start.begin();
        start.erase(start.begin());
        if (!seen.insert(name).second || !schemas.contains(name)) continue;
        std::set<std::string> next;
        collect_refs(schemas[name], next);
        for (const std::string& n : next)
            if (!seen.contains(n)) start.insert(n);
    }
    return seen;
}

// Whether a schema carries a "default" keyword (in itself or a nested schema, not following
// $refs; a member named "default" in "properties" is not one).
bool has_default(const json& node, bool member_map = false) {
    if (node.is_array()) {
        for (const json& item : node)
            if (has_default(item)) return true;
        return false;
    }
    if (!node.is_object()) return false;
    for (const auto& [key, value] : node.items()) {
        if (!member_map && key == "default") return true;
        if (has_default(value, !member_map && (key == "properties" || key == "patternProperties")))
            return true;
    }
    return false;
}

// Removes the "default" keywords of a schema and points its $refs at the renamed components.
void strip_defaults(json& node, const std::map<std::string, std::string>& renamed,
                    bool member_map = false) {
    if (node.is_array()) {
        for (json& item : node) strip_defaults(item, renamed);
        return;
    }
    if (!node.is_object()) return;
    if (!member_map) node.erase("default");
    for (auto& [key, value] : node.items()) {
        if (key == "$ref" && value.is_string()) {
            const std::string target = value;
            if (target.rfind(schema_prefix, 0) != 0) continue;
            const auto found = renamed.find(target.substr(schema_prefix.size()));
            if (found != renamed.end()) value = std::string(schema_prefix) + found->second;
        } else {
            strip_defaults(value, renamed,
                           !member_map && (key == "properties" || key == "patternProperties"));
        }
    }
}

}  // namespace openapi_http_detail

void split_request_components(nlohmann::json& document) {
    namespace oh = openapi_http_detail;
    nlohmann::json& schemas = document["components"]["schemas"];
    std::set<std::string> request_roots, response_roots;
    for (auto& [path, item] : document["paths"].items()) {
        for (const std::string_view method : oh::methods) {
            if (!item.contains(method)) continue;
            const nlohmann::json& operation = item[std::string(method)];
            if (operation.contains("requestBody"))
                oh::collect_refs(operation["requestBody"], request_roots);
            if (operation.contains("responses"))
                oh::collect_refs(operation["responses"], response_roots);
        }
    }
    oh::collect_refs(document["components"]["responses"], response_roots);
    const std::set<std::string> requests = oh::closure(schemas, request_roots);
    const std::set<std::string> answers = oh::closure(schemas, response_roots);
    std::map<std::string, std::string> renamed;
    for (const std::string& name : requests) {
        const std::set<std::string> reached = oh::closure(schemas, {name});
        const bool defaulted =
            std::any_of(reached.begin(), reached.end(), [&](const std::string& n) {
                return schemas.contains(n) && oh::has_default(schemas[n]);
            });
        if (defaulted) renamed[name] = answers.contains(name) ? name + "Input" : name;
    }
    for (const auto& [name, target] : renamed) {
        nlohmann::json schema = schemas[name];
        oh::strip_defaults(schema, renamed);
        if (target != name) {
            schema["description"] = schema.value("description", std::string()) +
                                    " (As a request takes it: the defaults are " + name + "'s.)";
        }
        schemas[target] = std::move(schema);
    }
    for (auto& [path, item] : document["paths"].items()) {
        for (const std::string_view method : oh::methods) {
            if (item.contains(method) && item[std::string(method)].contains("requestBody"))
                oh::strip_defaults(item[std::string(method)]["requestBody"], renamed);
        }
    }
}

void add_http_conventions(nlohmann::json& document) {
    namespace oh = openapi_http_detail;
    for (auto& [name, response] : document["components"]["responses"].items())
        oh::add_headers(response, false);
    const nlohmann::json request_id = oh::ref("parameters", "X-Request-Id");
    for (auto& [path, item] : document["paths"].items()) {
        for (const std::string_view method : oh::methods) {
            if (!item.contains(method)) continue;
            nlohmann::json& operation = item[std::string(method)];
            nlohmann::json& parameters = operation["parameters"];
            if (parameters.is_null()) parameters = nlohmann::json::array();
            bool has_id = false;
            for (const nlohmann::json& parameter : parameters)
                has_id = has_id || parameter == request_id;
            if (!has_id) parameters.push_back(request_id);
            nlohmann::json& responses = operation["responses"];
            for (const auto& [status, component] : oh::transport) {
                if (!responses.contains(status))
                    responses[std::string(status)] = oh::ref("responses", component);
            }
            for (auto& [status, response] : responses.items())
                oh::add_headers(response, status == "202");
            if (operation.contains("requestBody")) {
                nlohmann::json& body = operation["requestBody"];
                const nlohmann::json* given = oh::body_schema(body);
                body["required"] = given != nullptr && !oh::accepts_empty_object(document, *given);
            }
        }
    }
}

}  // namespace rollgap::service
