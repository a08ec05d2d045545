// JSON Merge Patch (RFC 7396) and what it means for a request's scenario: a patch onto the
// default scenario, where null restores the default. The merge itself is nlohmann::json's;
// the RFC's own examples pin the semantics the scenario reading relies on.

#include <doctest/doctest.h>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/scenario_json.h"

using nlohmann::json;

namespace {

json merge_patch(json target, const json& patch) {
    target.merge_patch(patch);
    return target;
}

}  // namespace

TEST_CASE("merge patch reproduces every example of RFC 7396 Appendix A") {
    struct Example {
        const char* target;
        const char* patch;
        const char* result;
    };
    const Example examples[] = {
        {R"({"a":"b"})", R"({"a":"c"})", R"({"a":"c"})"},
        {R"({"a":"b"})", R"({"b":"c"})", R"({"a":"b","b":"c"})"},
        {R"({"a":"b"})", R"({"a":null})", R"({})"},
        {R"({"a":"b","b":"c"})", R"({"a":null})", R"({"b":"c"})"},
        {R"({"a":["b"]})", R"({"a":"c"})", R"({"a":"c"})"},
        {R"({"a":"c"})", R"({"a":["b"]})", R"({"a":["b"]})"},
        {R"({"a":{"b":"c"}})", R"({"a":{"b":"d","c":null}})", R"({"a":{"b":"d"}})"},
        {R"({"a":[{"b":"c"}]})", R"({"a":[1]})", R"({"a":[1]})"},
        {R"(["a","b"])", R"(["c","d"])", R"(["c","d"])"},
        {R"({"a":"b"})", R"(["c"])", R"(["c"])"},
        {R"({"a":"foo"})", R"(null)", R"(null)"},
        {R"({"a":"foo"})", R"("bar")", R"("bar")"},
        {R"({"e":null})", R"({"a":1})", R"({"e":null,"a":1})"},
        {R"([1,2])", R"({"a":"b","c":null})", R"({"a":"b"})"},
        {R"({})", R"({"a":{"bb":{"ccc":null}}})", R"({"a":{"bb":{}}})"},
    };
    for (const Example& example : examples) {
        CAPTURE(example.target);
        CAPTURE(example.patch);
        CHECK(merge_patch(json::parse(example.target), json::parse(example.patch)) ==
              json::parse(example.result));
    }
}

TEST_CASE("merge patch leaves members the patch does not name untouched") {
    const json target = {{"strip", {{"width_mm", 1800}, {"reduction", 0.15}}},
                         {"rolls", {{"radius_mm", 280}}}};
    const json patched = merge_patch(target, {{"strip", {{"reduction", 0.2}}}});
    CHECK(patched["strip"]["reduction"] == 0.2);
    CHECK(patched["strip"]["width_mm"] == 1800);
    CHECK(patched["rolls"] == target["rolls"]);
}

TEST_CASE("an empty scenario patch is the default scenario") {
    rollgap::api::FieldErrors errors;
    const auto scenario = rollgap::api::scenario_from_patch(json::object(), "/scenario", errors);
    CHECK(errors.empty());
    CHECK(rollgap::api::resolved_scenario_json(scenario) == rollgap::api::default_scenario_json());
}

TEST_CASE("null in a scenario patch restores the default instead of removing the field") {
    rollgap::api::FieldErrors errors;
    const json patch = {{"rolls", {{"radius_mm", nullptr}, {"speed_m_per_s", 5.0}}},
                        {"strip", nullptr}};
    const auto scenario = rollgap::api::scenario_from_patch(patch, "/scenario", errors);
    REQUIRE(errors.empty());
    const json resolved = rollgap::api::resolved_scenario_json(scenario);
    const json defaults = rollgap::api::default_scenario_json();
    CHECK(resolved["rolls"]["radius_mm"] == defaults["rolls"]["radius_mm"]);
    CHECK(resolved["rolls"]["speed_m_per_s"] == 5.0);
    CHECK(resolved["strip"] == defaults["strip"]);
}

TEST_CASE("a scenario patch that replaces a group by a non-object is a type error at that group") {
    rollgap::api::FieldErrors errors;
    rollgap::api::scenario_from_patch({{"strip", json::array({1, 2})}}, "/scenario", errors);
    REQUIRE(errors.size() == 1);
    CHECK(errors.reported()[0].pointer == "/scenario/strip");
}
