// The field glossary: every row of the scenario field table and every option of every analysis
// is described for a plant engineer, and the one description reaches the OpenAPI document, the
// command line's `scenario --explain` and, for a fraction given as a percentage, the problem.

#include <doctest/doctest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/plant_units.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"
#include "api/tandem_json.h"
#include "api/tandem_schema.h"
#include "service/cli.h"
#include "service/evaluate.h"
#include "service/openapi.h"

using nlohmann::json;
using namespace rollgap;

namespace {

bool contains(std::string_view text, std::string_view part) {
    return text.find(part) != std::string_view::npos;
}

std::string cli_output(std::vector<std::string_view> arguments, int& status) {
    std::istringstream in;
    std::ostringstream out, err;
    status = service::run_cli(arguments, in, out, err);
    return out.str();
}

// The property schema of a scenario field in a served scenario schema (Scenario or ScenarioPatch).
const json& property_at(const json& schema, std::string_view path) {
    const json* node = &schema;
    std::size_t start = 1;
    while (start <= path.size()) {
        std::size_t end = path.find('/', start);
        if (end == std::string_view::npos) end = path.size();
        node = &node->at("properties").at(std::string(path.substr(start, end - start)));
        start = end + 1;
    }
    return *node;
}

// Every leaf property below `schema` (nested objects and array items included), with its path.
void collect_option_properties(const json& schema, const std::string& path,
                               std::vector<std::pair<std::string, json>>& out) {
    if (!schema.contains("properties")) return;
    for (const auto& [name, property] : schema.at("properties").items()) {
        const std::string at = path + "/" + name;
        if (property.contains("$ref")) continue;  // a schema of its own, visited as such
        out.emplace_back(at, property);
        collect_option_properties(property, at, out);
        if (property.contains("items")) out.emplace_back(at + "/items", property.at("items"));
    }
}

}  // namespace

TEST_CASE("glossary: every scenario field has a description a plant engineer can use") {
    for (const api::ScenarioField& field : api::scenario_fields()) {
        CAPTURE(field.path);
        const std::string& text = field.description;
        REQUIRE(text.size() > 40);  // a sentence, not a label
        CHECK(text.back() == '.');
        if (field.kind == api::FieldKind::number && field.unit.code != "1") {
            // typical values are stated in the field's own unit, as the client writes it
            CHECK(contains(text, field.unit.code));
        }
        if (field.kind == api::FieldKind::number && field.unit.code == "1") {
            CHECK((contains(text, "dimensionless") || contains(text, "fraction")));
        }
        if (field.kind == api::FieldKind::choice) {
            for (const std::string_view choice : field.choices)
                CHECK(contains(text, std::string(choice) + " ="));
        }
    }
    const api::ScenarioField* reduction = api::find_scenario_field("/strip/reduction");
    REQUIRE(reduction != nullptr);
    CHECK(contains(reduction->description, "fraction: 0.25 = 25 %"));
    // Why there is no k4 is said where a client looks for it: at every stiffness.
    for (const api::ScenarioField& field : api::scenario_fields()) {
        if (field.path.starts_with("/mill/stiffness_GN_per_m/")) {
            CAPTURE(field.path);
            CHECK(contains(field.description, "no k4"));
        }
    }
}

TEST_CASE("glossary: the served OpenAPI document carries each field's description verbatim") {
    const json document = json::parse(service::openapi_text());
    for (const char* schema_name : {"Scenario", "ScenarioPatch"}) {
        const json& schema = document.at("components").at("schemas").at(schema_name);
        for (const api::ScenarioField& field : api::scenario_fields()) {
            CAPTURE(schema_name);
            CAPTURE(field.path);
            const std::string description =
                property_at(schema, field.path).at("description").get<std::string>();
            // the glossary first, then the generated type, unit and bounds
            CHECK(description.starts_with(field.description + " "));
            if (field.kind == api::FieldKind::number)
                CHECK(contains(description, field.range.text()));
        }
    }
}

TEST_CASE("glossary: every option of every analysis is described in the served OpenAPI document") {
    const json document = json::parse(service::openapi_text());
    std::size_t described = 0;
    for (const auto& [name, schema] : document.at("components").at("schemas").items()) {
        if (!name.ends_with("Options")) continue;
        const std::string& schema_name = name;  // clang 14 cannot CAPTURE a structured binding
        CAPTURE(schema_name);
        CHECK(!schema.value("description", "").empty());
        std::vector<std::pair<std::string, json>> properties;
        collect_option_properties(schema, "", properties);
        for (const auto& [path, property] : properties) {
            const std::string& option = path;  // clang 14 cannot CAPTURE a structured binding
            CAPTURE(option);
            const std::string description = property.value("description", "");
            // more than the generated type/unit/bounds sentence
            CHECK(description.size() > 20);
            CHECK(!description.starts_with("Number;"));
            CHECK(!description.starts_with("Integer;"));
            ++described;
        }
    }
    CHECK(described >= 30);
}

TEST_CASE(
    "glossary: rollgap scenario --explain lists every field with unit, bounds, default and description") {
    int status = -1;
    const std::string text = cli_output({"scenario", "--explain"}, status);
    CHECK(status == service::exit_success);
    const json defaults = api::default_scenario_json();
    std::size_t position = 0;
    for (const api::ScenarioField& field : api::scenario_fields()) {
        CAPTURE(field.path);
        // in table order, each on its own line, starting with the pointer
        const std::size_t at = text.find("\n" + field.path + " ", position);
        REQUIRE(at != std::string::npos);
        position = at + 1;
        const std::string line = text.substr(at + 1, text.find('\n', at + 1) - at - 1);
        const json& value = defaults.at(json::json_pointer(field.path));
        CHECK(contains(line, value.is_string() ? value.get<std::string>() : value.dump()));
        if (field.kind == api::FieldKind::number) {
            CHECK(contains(line, field.unit.code));
            CHECK(contains(line, field.range.text()));
        }
        // the description follows, wrapped: its words in order
        std::string words;
        const std::size_t next_field =
            std::min(text.find("\n/", at + 1), text.find("\n\nThe tandem mill's fields", at + 1));
        std::istringstream body(
            text.substr(at + 1 + line.size(), next_field - at - 1 - line.size()));
        for (std::string word; body >> word;) words += (words.empty() ? "" : " ") + word;
        CHECK(words == field.description);
    }
    std::vector<std::string_view> bad{"scenario", "--explian"};
    (void)cli_output(bad, status);
    CHECK(status == service::exit_bad_input);
}

TEST_CASE("glossary: the tandem document's fields are described in OpenAPI and --explain") {
    const json document = json::parse(service::openapi_text());
    int status = -1;
    const std::string text = cli_output({"scenario", "--explain"}, status);
    const std::size_t section = text.find("The tandem mill's fields");
    REQUIRE(section != std::string::npos);
    const json defaults = api::default_tandem_json();
    for (const api::TandemField& field : api::tandem_fields()) {
        CAPTURE(field.path);
        REQUIRE(field.description.size() > 40);
        CHECK(field.description.back() == '.');
        if (field.kind != api::TandemFieldKind::choice && field.unit.code != "1")
            CHECK(contains(field.description, field.unit.code));
        if (field.kind == api::TandemFieldKind::choice) {
            for (const std::string_view choice : field.choices)
                CHECK(contains(field.description, std::string(choice) + " ="));
        }
        for (const char* schema_name : {"Tandem", "TandemPatch"}) {
            CAPTURE(schema_name);
            const json& schema = document.at("components").at("schemas").at(schema_name);
            const std::string description =
                property_at(schema, field.path).at("description").get<std::string>();
            CHECK(description.starts_with(field.description + " "));
            if (field.kind != api::TandemFieldKind::choice)
                CHECK(contains(description, field.range.text()));
        }
        // --explain: the pointer's line in the tandem section with its default, then the text
        const std::size_t at = text.find("\n" + field.path + " ", section);
        REQUIRE(at != std::string::npos);
        const std::string line = text.substr(at + 1, text.find('\n', at + 1) - at - 1);
        const json& value = defaults.at(json::json_pointer(field.path));
        CHECK(contains(line, value.is_string() ? value.get<std::string>() : value.dump()));
        const std::size_t next = text.find("\n/", at + 1);
        std::istringstream body(text.substr(at + 1 + line.size(), next - at - 1 - line.size()));
        std::string words;
        for (std::string word; body >> word;) words += (words.empty() ? "" : " ") + word;
        CHECK(words == field.description);
    }
    CHECK(contains(text.substr(section), "\n/stands "));
    CHECK(contains(text.substr(section), "\n/stand_defaults "));
}

TEST_CASE(
    "glossary: a fraction given as a percentage gets the hint, other bound violations do not") {
    const auto detail_of = [](const std::string& request) {
        const service::Outcome outcome = service::evaluate_text(request);
        REQUIRE(outcome.problem.has_value());
        REQUIRE(outcome.body.at("errors").size() == 1);
        return outcome.body.at("errors").at(0).at("detail").get<std::string>();
    };
    const std::string percent =
        detail_of(R"({"analysis":"roll_gap","scenario":{"strip":{"reduction":25}}})");
    CHECK(contains(percent, "25 is outside (0, 0.7]"));
    CHECK(contains(percent, "fraction, 0.25 = 25 %"));
    CHECK(contains(percent, "write 0.25"));
    // 0.8 and 80 (0.8 as a fraction is out of range too) are plain violations
    CHECK(!contains(detail_of(R"({"analysis":"roll_gap","scenario":{"strip":{"reduction":0.8}}})"),
                    "fraction"));
    CHECK(!contains(detail_of(R"({"analysis":"roll_gap","scenario":{"strip":{"reduction":80}}})"),
                    "fraction"));
    // a field with a unit is never a fraction
    CHECK(!contains(
        detail_of(R"({"analysis":"roll_gap","scenario":{"strip":{"entry_thickness_mm":50}}})"),
        "fraction"));
}

TEST_CASE("glossary: plant units are listed in the patch schemas and in --explain") {
    const json document = json::parse(service::openapi_text());
    const json& schemas = document.at("components").at("schemas");
    int status = -1;
    const std::string text = cli_output({"scenario", "--explain"}, status);
    // each row of the table, where its canonical member is: the alternate property beside it
    // (patches only: answers are canonical) and the explain text naming it
    const std::pair<const char*, const char*> where[] = {
        {"/rolls/speed_m_per_s", "speed_m_per_min"},
        {"/rolls/speed_m_per_s", "speed_mm_per_s"},
        {"/lubricant/viscosity_Pa_s", "viscosity_mPa_s"},
        {"/rolls/radius_mm", "diameter_mm"},
        {"/mill/masses_t", "masses_kg"},
        {"/mill/stiffness_GN_per_m", "stiffness_kN_per_mm"},
        {"/mill/damping_MN_s_per_m", "damping_kN_s_per_m"},
        {"/tension/back/stress_MPa", "force_kN"},
        {"/tension/back/amplitude_MPa", "amplitude_kN"}};
    std::size_t listed = 0;
    for (const auto& entry : where) {
        const char* path = entry.first;
        const std::string key = entry.second;
        CAPTURE(key);
        const std::string_view p = path;
        const std::string group(p.substr(0, p.rfind('/')));
        const json& patch_group = group.empty() ? schemas.at("ScenarioPatch")
                                                : property_at(schemas.at("ScenarioPatch"), group);
        REQUIRE(patch_group.at("properties").contains(key));
        const json& alternate = patch_group.at("properties").at(key);
        // exact, or (a force over the strip's cross-section) converted once the layers merge
        CHECK((contains(alternate.at("description").get<std::string>(), "converted exactly") ||
               contains(alternate.at("description").get<std::string>(),
                        "converted when the scenario is read")));
        const json& canonical = property_at(schemas.at("ScenarioPatch"), path);
        bool named = false;
        for (const json& a : canonical.at("x-alternate-units")) named = named || a.at("key") == key;
        CHECK(named);
        const json& full_group =
            group.empty() ? schemas.at("Scenario") : property_at(schemas.at("Scenario"), group);
        CHECK_FALSE(full_group.at("properties").contains(key));  // answers are canonical
        CHECK(contains(text, key));
        ++listed;
    }
    // the mill's tensions in kN: a list beside the spans' list, a number beside entry and exit
    const json& spans = property_at(schemas.at("TandemPatch"), "/spans");
    REQUIRE(spans.at("properties").contains("tension_kN"));
    CHECK(spans.at("properties").at("tension_kN").at("type").at(0) == "array");
    CHECK(property_at(schemas.at("TandemPatch"), "/entry")
              .at("properties")
              .at("tension_kN")
              .at("type")
              .at(0) == "number");
    CHECK_FALSE(
        property_at(schemas.at("Tandem"), "/spans").at("properties").contains("tension_kN"));
    CHECK(contains(text, "tension_kN"));
    ++listed;
    CHECK(listed == api::alternate_units().size());
    // the mill's speed in m/min
    CHECK(schemas.at("TandemPatch").at("properties").contains("speed_m_per_min"));
    CHECK_FALSE(schemas.at("Tandem").at("properties").contains("speed_m_per_min"));
}
