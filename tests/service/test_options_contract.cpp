// What the OpenAPI document says of every analysis' options is what the service enforces: each
// bounded number or integer the document states, in every options component an analysis
// reaches (its own, and those its members refer to), sent just outside its bounds, is a 422
// problem at that member's pointer with the document's bound and unit; each boolean sent as a
// number is one at its pointer. The scalar options are rows of api/option_table.h (written once
// for reader and document); this walks the document, so a component listing a row its reader
// does not read, or a reader using other bounds, fails here by name.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/interval.h"
#include "api/option_table.h"
#include "service/analyses/table.h"
#include "service/evaluate.h"
#include "service/openapi.h"

using nlohmann::json;
using namespace rollgap;

namespace {

constexpr std::string_view ref_prefix = "#/components/schemas/";

// The document's bounds of a property as the service writes a bound ("[0.01, 100]").
api::Interval bounds(const json& property) {
    api::Interval range{};
    range.min_open = property.contains("exclusiveMinimum");
    range.max_open = property.contains("exclusiveMaximum");
    range.min = property.at(range.min_open ? "exclusiveMinimum" : "minimum").get<double>();
    range.max = property.at(range.max_open ? "exclusiveMaximum" : "maximum").get<double>();
    return range;
}

std::vector<json> outside(const api::Interval& range, bool integer) {
    const auto step = [integer](double at) {
        return integer ? 1.0 : std::max(std::fabs(at) * 1e-3, 1e-300);
    };
    const double below = range.min_open ? range.min : range.min - step(range.min);
    const double above = range.max_open ? range.max : range.max + step(range.max);
    if (integer) return {json(static_cast<long long>(below)), json(static_cast<long long>(above))};
    return {json(below), json(above)};
}

struct Walk {
    const json& schemas;
    std::set<std::string> components_seen;
    int members_checked = 0;

    // The errors of `request` (which must be refused).
    static std::vector<json> refused(const json& request) {
        const auto prepared = service::prepare(request);
        const auto* outcome = std::get_if<service::Outcome>(&prepared);
        REQUIRE_MESSAGE(outcome != nullptr, "accepted: ", request.dump());
        CHECK(outcome->http_status == 422);
        return outcome->body.value("errors", json::array()).get<std::vector<json>>();
    }

    // Checks the options component `component`, found at `at` (a JSON pointer below /options)
    // in the options of `request`, whose other members are valid.
    void component(const std::string& name, const json& request, const json::json_pointer& at,
                   const std::set<std::string>& own_entries) {
        CAPTURE(name);
        components_seen.insert(name);
        const json& properties = schemas.at(name).at("properties");
        for (const auto& [member, property] : properties.items()) {
            const json::json_pointer pointer = at / member;
            const std::string problem_pointer = "/options" + pointer.to_string();
            CAPTURE(problem_pointer);
            if (const auto ref = property.find("$ref"); ref != property.end()) {
                const std::string target = ref->get<std::string>().substr(ref_prefix.size());
                // A component with its own minimal options (a sweep's amplitude needs
                // quantity "amplitude") is walked from those.
                if (own_entries.count(target) == 0)
                    component(target, request, pointer, own_entries);
                continue;
            }
            // A list of objects of a component (a mill's per-stand limits): its first item
            // walked, the list of one item otherwise as the request leaves it.
            if (const auto items = property.find("items");
                items != property.end() && items->contains("allOf")) {
                const std::string target =
                    items->at("allOf").at(0).at("$ref").get<std::string>().substr(
                        ref_prefix.size());
                component(target, request, pointer / "0", own_entries);
                continue;
            }
            std::string type;
            if (property.contains("type") && property.at("type").is_array()) {
                for (const json& t : property.at("type"))
                    if (t != "null") type = t.get<std::string>();
            } else {
                type = property.value("type", "");
            }
            if (type == "boolean") {
                json bad = request;
                bad["options"][pointer] = 1;
                const std::vector<json> errors = refused(bad);
                CHECK(std::any_of(errors.begin(), errors.end(),
                                  [&](const json& e) { return e["pointer"] == problem_pointer; }));
                ++members_checked;
                continue;
            }
            if ((type != "number" && type != "integer") ||
                !(property.contains("minimum") || property.contains("exclusiveMinimum"))) {
                continue;
            }
            const api::Interval range = bounds(property);
            const std::string unit = property.value("x-unit", "1");
            for (const json& value : outside(range, type == "integer")) {
                CAPTURE(value);
                json bad = request;
                bad["options"][pointer] = value;
                const std::vector<json> errors = refused(bad);
                CAPTURE(json(errors).dump());
                CHECK(std::any_of(errors.begin(), errors.end(), [&](const json& e) {
                    return e["pointer"] == problem_pointer &&
                           e.value("bound", "") == range.text() &&
                           (type == "integer" || e.value("unit", "") == unit);
                }));
            }
            ++members_checked;
        }
    }
};

}  // namespace

TEST_CASE(
    "options: every bounded option in the OpenAPI document is enforced with the document's "
    "bound and unit, at its pointer") {
    const json document = service::openapi_document();
    Walk walk{document.at("components").at("schemas"), {}, 0};
    for (const service::Analysis& analysis : service::analyses()) {
        CAPTURE(analysis.name);
        std::set<std::string> own_entries;
        for (const service::OptionsDefaults& entry : analysis.options_defaults)
            own_entries.insert(std::string(entry.schema));
        for (const service::OptionsDefaults& entry : analysis.options_defaults) {
            const json request = {{"analysis", analysis.name},
                                  {"options", json::parse(entry.minimal_options)}};
            // The minimal request itself is valid.
            CHECK(std::holds_alternative<service::PreparedRequest>(service::prepare(request)));
            json::json_pointer at;
            if (!entry.member.empty()) at = at / std::string(entry.member);
            walk.component(std::string(entry.schema), request, at, own_entries);
        }
    }
    MESSAGE(walk.members_checked << " option members checked in " << walk.components_seen.size()
                                 << " components");
    // Every component of the option table was reached from some analysis.
    for (const api::OptionComponent& component : api::option_components())
        CHECK_MESSAGE(walk.components_seen.count(std::string(component.schema)) == 1,
                      component.schema, " is reached by no analysis");
}

TEST_CASE(
    "options: every member of every options component has a title, unique within it, and a "
    "fit's quantities their titles and units") {
    const json document = service::openapi_document();
    const json& schemas = document.at("components").at("schemas");
    int titled = 0;
    for (const auto& component : schemas.items()) {
        const std::string name = component.key();  // a plain local: CAPTURE takes it by lambda
        if (name.find("Options") == std::string::npos && name != "MapAxis") continue;
        CAPTURE(name);
        std::set<std::string> titles;
        const json properties = component.value().value("properties", json::object());
        for (const auto& entry : properties.items()) {
            const std::string member = entry.key();
            const json& property = entry.value();
            CAPTURE(member);
            REQUIRE(property.contains("title"));
            const std::string title = property.at("title").get<std::string>();
            CHECK(!title.empty());
            CHECK(title != member);  // a name, not the key again
            CHECK_MESSAGE(titles.insert(title).second, "two members titled ", title);
            ++titled;
        }
    }
    MESSAGE(titled << " option members titled");
    // The scalar rows' titles are the document's (one table for both).
    const json& search = schemas.at("CriticalSpeedSearchOptions").at("properties");
    CHECK(search.at("relative_tolerance").at("title") ==
          api::option(api::OptionId::search_tolerance).title);
    CHECK(schemas.at("AmplitudeOptions").at("properties").at("relative_tolerance").at("title") ==
          api::option(api::OptionId::integration_tolerance).title);

    // A fit's quantities: the enum, its titles and units in the same order, the unit the one
    // the quantity's name ends with.
    const json& quantity = schemas.at("CalibrateOptions")
                               .at("properties")
                               .at("observations")
                               .at("items")
                               .at("properties")
                               .at("quantity");
    const json& names = quantity.at("enum");
    REQUIRE(quantity.at("x-enum-descriptions").size() == names.size());
    REQUIRE(quantity.at("x-units").size() == names.size());
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string name = names[i].get<std::string>();
        const std::string unit = quantity.at("x-units")[i].get<std::string>();
        CAPTURE(name);
        CHECK(!quantity.at("x-enum-descriptions")[i].get<std::string>().empty());
        const std::string suffix = unit == "kN.m"  ? "_kN_m"
                                   : unit == "m/s" ? "_m_per_s"
                                                   : "_" + unit;
        if (unit == "1") CHECK(name.find("_Hz") == std::string::npos);
        else CHECK(name.size() > suffix.size());
        if (unit != "1")
            CHECK(name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0);
    }
}
