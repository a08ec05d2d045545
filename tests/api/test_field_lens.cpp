// The field lens (DECISIONS R): the scenario's field table addressed under a prefix, so that a
// plant document validates one stand where it sits (/tandem/stands/3/...), and every pointer in
// a problem carries the full path, array indices included.

#include <doctest/doctest.h>

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/scenario_json.h"
#include "api/scenario_schema.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::api;

namespace {

const FieldLens stand_3 = FieldLens().member("tandem").member("stands").element(3);

bool has_error_at(const FieldErrors& errors, const std::string& pointer) {
    for (const FieldError& error : errors.reported()) {
        if (error.pointer == pointer) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("a lens prefixes schema paths with its full pointer, array indices included") {
    CHECK(stand_3.prefix() == "/tandem/stands/3");
    CHECK(stand_3.pointer("/strip/reduction") == "/tandem/stands/3/strip/reduction");
    CHECK(stand_3.pointer("") == "/tandem/stands/3");
    CHECK(FieldLens().pointer("/strip/reduction") == "/strip/reduction");
    // member names are escaped as RFC 6901 tokens
    CHECK(FieldLens().member("a/b").member("c~d").prefix() == "/a~1b/c~0d");
    const auto pointers = stand_3.field_pointers();
    REQUIRE(pointers.size() == scenario_fields().size());
    for (std::size_t i = 0; i < pointers.size(); ++i)
        CHECK(pointers[i] == "/tandem/stands/3" + scenario_fields()[i].path);
}

TEST_CASE("a lens finds fields and groups by full pointer, and nothing outside its prefix") {
    const ScenarioField* reduction = stand_3.find_field("/tandem/stands/3/strip/reduction");
    REQUIRE(reduction != nullptr);
    CHECK(reduction == find_scenario_field("/strip/reduction"));
    CHECK(stand_3.schema_path("/tandem/stands/3/strip/reduction") == "/strip/reduction");
    CHECK(stand_3.schema_path("/tandem/stands/3") == "");
    // another stand, an index that only starts with 3, the bare schema path: not under the lens
    CHECK(stand_3.find_field("/tandem/stands/2/strip/reduction") == nullptr);
    CHECK(stand_3.find_field("/tandem/stands/30/strip/reduction") == nullptr);
    CHECK_FALSE(stand_3.schema_path("/tandem/stands/30/strip/reduction").has_value());
    CHECK(stand_3.find_field("/strip/reduction") == nullptr);
    CHECK(stand_3.find_field("/tandem/stands/3/strip/no_such_field") == nullptr);

    CHECK(stand_3.is_group("/tandem/stands/3"));
    CHECK(stand_3.is_group("/tandem/stands/3/tension/back"));
    CHECK_FALSE(stand_3.is_group("/tandem/stands/3/strip/reduction"));
    CHECK_FALSE(stand_3.is_group("/tandem/stands/31/tension/back"));
    CHECK(stand_3.group_members("/tandem/stands/3").size() == scenario_group_members("").size());
    CHECK(stand_3.group_members("/tandem/stands/4").empty());
}

TEST_CASE("a stand validated through a lens reports problems at their full pointers") {
    json plant = {{"tandem", {{"stands", json::array()}}}};
    for (int i = 0; i < 5; ++i) plant["tandem"]["stands"].push_back(json::object());
    plant["tandem"]["stands"][3] = {{"strip", {{"reduction", 2.0}, {"widht_mm", 1000}}},
                                    {"tension", {{"back", "not an object"}}}};
    const json& stand = plant[json::json_pointer(stand_3.prefix())];

    FieldErrors errors;
    scenario_from_patch(stand, stand_3.prefix(), errors);
    REQUIRE_FALSE(errors.empty());
    CHECK(has_error_at(errors, stand_3.pointer("/strip/reduction")));
    CHECK(has_error_at(errors, "/tandem/stands/3/strip/widht_mm"));
    CHECK(has_error_at(errors, "/tandem/stands/3/tension/back"));
    for (const FieldError& error : errors.reported()) {
        CHECK(error.pointer.starts_with("/tandem/stands/3/"));
    }

    // a stand without violations reads as the same scenario as on its own
    FieldErrors none;
    const core::Scenario on_its_own = scenario_from_patch(json::object(), "", none);
    const core::Scenario under_lens = scenario_from_patch(
        plant["tandem"]["stands"][0],
        FieldLens().member("tandem").member("stands").element(0).prefix(), none);
    CHECK(none.empty());
    CHECK(resolved_scenario_json(under_lens) == resolved_scenario_json(on_its_own));
}
