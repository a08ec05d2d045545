#pragma once
// A result writer as a table: one row per JSON member (its name with the unit, a description,
// the JSON Schema of its value, a getter). The same rows write the JSON, give the OpenAPI
// schema of the result (service/openapi.cpp) and name the CSV columns (api/csv.h), so the
// three cannot drift apart.
// An analysis' result: a ResultTable of its members (nested objects are tables of their own,
// referenced with ref_schema), whose components its <name>_result_schemas() lists for the
// analysis' row (service/analyses/analysis.h says what adding an analysis takes).

#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/units.h"

namespace rollgap::api {

// Value schemas of the members (JSON Schema 2020-12, as OpenAPI 3.1 uses it). A number carries
// its UCUM unit in x-unit; `nullable`: a figure the outcome did not produce is null.
nlohmann::json number_schema(Unit unit, bool nullable = true);
nlohmann::json integer_schema(bool nullable = false);
nlohmann::json boolean_schema(bool nullable = false);
nlohmann::json string_schema();
nlohmann::json enum_schema(std::initializer_list<std::string_view> choices, bool nullable = false);
nlohmann::json ref_schema(std::string_view component, bool nullable = false);
nlohmann::json array_schema(nlohmann::json items);

// A member absent from this result: a getter returns it to leave the member out.
inline nlohmann::json absent() { return nlohmann::json(nlohmann::json::value_t::discarded); }

template <class T>
struct Member {
    std::string_view name;         // the JSON name, unit included
    std::string_view description;  // for people; the unit is added from x-unit
    nlohmann::json schema;         // of the value
    std::function<nlohmann::json(const T&)> get;
    bool optional = false;  // may be absent (the getter returns absent())
};

// The JSON Schema of an object with these members: every member described, the members that
// are always present required, no others allowed.
nlohmann::json object_schema(
    std::string_view description,
    const std::vector<std::pair<std::string_view, nlohmann::json>>& properties,
    const std::vector<std::string_view>& required);

template <class T>
class ResultTable {
public:
    ResultTable(std::string_view component, std::string_view description,
                std::vector<Member<T>> members)
        : component_(component), description_(description), members_(std::move(members)) {}

    nlohmann::json write(const T& value) const {
        nlohmann::json body = nlohmann::json::object();
        for (const Member<T>& member : members_) {
            nlohmann::json item = member.get(value);
            if (!item.is_discarded()) body[std::string(member.name)] = std::move(item);
        }
        return body;
    }

    nlohmann::json schema() const {
        std::vector<std::pair<std::string_view, nlohmann::json>> properties;
        std::vector<std::string_view> required;
        for (const Member<T>& member : members_) {
            nlohmann::json property = member.schema;
            property["description"] = std::string(member.description);
            properties.emplace_back(member.name, std::move(property));
            if (!member.optional) required.push_back(member.name);
        }
        return object_schema(description_, properties, required);
    }

    // The member names in table order (the order of CSV columns).
    std::vector<std::string> names() const {
        std::vector<std::string> names;
        for (const Member<T>& member : members_) names.emplace_back(member.name);
        return names;
    }

    // The members with a single value (not an array or an object): the columns of a row.
    std::vector<std::string> scalar_names() const {
        std::vector<std::string> names;
        for (const Member<T>& member : members_) {
            const nlohmann::json& schema = member.schema;
            if (!schema.contains("items") && !schema.contains("$ref") &&
                !schema.contains("oneOf")) {
                names.emplace_back(member.name);
            }
        }
        return names;
    }

    std::string_view component() const { return component_; }

private:
    std::string_view component_;
    std::string_view description_;
    std::vector<Member<T>> members_;
};

// The members of a part of Outer (`part` returns it) as members of Outer: a result that embeds
// another's members flat.
template <class Outer, class Inner, class Part>
std::vector<Member<Outer>> lift(std::vector<Member<Inner>> members, Part part) {
    std::vector<Member<Outer>> lifted;
    for (Member<Inner>& member : members) {
        lifted.push_back(
            {member.name, member.description, std::move(member.schema),
             [get = std::move(member.get), part](const Outer& outer) { return get(part(outer)); },
             member.optional});
    }
    return lifted;
}

// A component schema of the OpenAPI document, from a table.
struct ResultSchema {
    std::string_view component;
    nlohmann::json schema;
};

template <class T>
ResultSchema result_schema(const ResultTable<T>& table) {
    return {table.component(), table.schema()};
}

}  // namespace rollgap::api
