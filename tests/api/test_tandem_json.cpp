// The tandem document (docs/model.md §12.8): the mill's field table wired to core::Mill, the
// stands as scenario patches over shared defaults, the echo that reruns to the same mill, and
// every violation reported at its pointer (a stand's own field at /tandem/stands/N/..., a value
// the mill gives a stand at the mill field that gives it).

#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/scenario_json.h"
#include "api/tandem_json.h"
#include "api/tandem_schema.h"
#include "api/units.h"
#include "core/mill/mill.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::api;

namespace {

core::Mill read_clean(const json& patch) {
    FieldErrors errors;
    const core::Mill mill = mill_from_patch(patch, "/tandem", errors);
    for (const FieldError& error : errors.reported())
        FAIL_CHECK(error.pointer << ": " << error.detail);
    return mill;
}

std::vector<std::string> pointers_of(const json& patch) {
    FieldErrors errors;
    (void)mill_from_patch(patch, "/tandem", errors);
    std::vector<std::string> pointers;
    for (const FieldError& error : errors.reported()) pointers.push_back(error.pointer);
    return pointers;
}

bool has(const std::vector<std::string>& pointers, const std::string& pointer) {
    return std::find(pointers.begin(), pointers.end(), pointer) != pointers.end();
}

}  // namespace

TEST_CASE("the empty patch is core's default mill, and its echo reads back to the same mill") {
    const core::Mill mill = read_clean(json::object());
    const core::Mill reference = core::default_mill();
    CHECK(mill.thickness == reference.thickness);
    CHECK(mill.span_length == reference.span_length);
    CHECK(mill.interstand_tension == reference.interstand_tension);
    CHECK(mill.entry_tension == reference.entry_tension);
    CHECK(mill.exit_tension == reference.exit_tension);
    CHECK(mill.speed == reference.speed);
    CHECK(mill.width == reference.width);
    CHECK(mill.entry == reference.entry);
    CHECK(mill.exit == reference.exit);
    REQUIRE(mill.size() == reference.size());
    // every stand is the default scenario (the fields the mill gives are the mill's)
    for (int i = 0; i < mill.size(); ++i) {
        CHECK(resolved_scenario_json(core::stand_scenario(mill, i, 10.0)) ==
              resolved_scenario_json(core::stand_scenario(reference, i, 10.0)));
    }
    // The echo is a complete document that reruns to itself.
    const json echo = resolved_tandem_json(mill);
    FieldErrors errors;
    const core::Mill again = mill_from_json(echo, "/tandem", errors);
    CHECK(errors.empty());
    CHECK(resolved_tandem_json(again) == echo);
    // and it carries no field the mill gives a stand
    for (const json& stand : echo["stands"]) {
        CHECK(!stand.contains("tension"));
        CHECK(!stand["strip"].contains("reduction"));
        CHECK(!stand["rolls"].contains("speed_m_per_s"));
    }
}

TEST_CASE("every field of the table reaches core::Mill and comes back in its unit") {
    // Each field set to a value inside its bounds that differs from the default, one at a time.
    for (const TandemField& field : tandem_fields()) {
        CAPTURE(field.path);
        json patch = json::object();
        const json::json_pointer at(field.path);
        switch (field.kind) {
            case TandemFieldKind::number: {
                const double value = field.integer                               ? 12.0
                                     : field.path == "/entry_thickness_mm"       ? 2.9
                                     : field.path.ends_with("tension_MPa")       ? 25.0
                                     : field.path == "/strip/density_kg_per_m3"  ? 7800.0
                                     : field.path == "/strip/width_mm"           ? 1250.0
                                     : field.path == "/strip/youngs_modulus_GPa" ? 205.0
                                     : field.path == "/speed_m_per_s"            ? 12.5
                                                                                 : 7.5;
                patch[at] = value;
                const core::Mill mill = read_clean(patch);
                CHECK(field.get(mill) == to_si(value, field.unit));
                CHECK(resolved_tandem_json(mill)[at] == value);
                break;
            }
            case TandemFieldKind::number_list: {
                const json values = field.path == "/exit_thickness_mm"
                                        ? json{2.5, 2.0, 1.7, 1.4, 1.1}
                                    : field.path == "/spans/length_m" ? json{4.0, 4.5, 5.5, 6.0}
                                                                      : json{80, 90, 100, 110};
                patch[at] = values;
                const core::Mill mill = read_clean(patch);
                const std::vector<double> got = field.get_list(mill);
                REQUIRE(got.size() == values.size());
                for (std::size_t i = 0; i < got.size(); ++i)
                    CHECK(got[i] == to_si(values[i].get<double>(), field.unit));
                CHECK(resolved_tandem_json(mill)[at] == values);
                break;
            }
            case TandemFieldKind::choice: {
                for (const std::string_view choice : field.choices) {
                    patch[at] = choice;
                    if (choice == "speeds") {  // then every stand gives its roll speed
                        patch["stands"] = json::array();
                        for (double v : {5.9, 7.1, 8.5, 10.1, 15.0})
                            patch["stands"].push_back({{"rolls", {{"speed_m_per_s", v}}}});
                    } else {
                        patch.erase("stands");
                    }
                    const core::Mill mill = read_clean(patch);
                    CHECK(field.read_choice(mill) == choice);
                }
                break;
            }
        }
    }
}

TEST_CASE("every bound of the table is enforced at the field's pointer") {
    for (const TandemField& field : tandem_fields()) {
        if (field.kind == TandemFieldKind::choice) continue;
        CAPTURE(field.path);
        const double outside = field.range.max * 1.5 + 1.0;
        json patch = json::object();
        const json::json_pointer at(field.path);
        if (field.kind == TandemFieldKind::number) {
            patch[at] = outside;
            CHECK(has(pointers_of(patch), "/tandem" + field.path));
        } else {
            json values = resolved_tandem_json(core::default_mill())[at];
            values[1] = outside;
            patch[at] = values;
            CHECK(has(pointers_of(patch), "/tandem" + field.path + "/1"));
        }
    }
}

TEST_CASE("stand_defaults reach every stand and a stand's own patch overrides them") {
    const core::Mill mill =
        read_clean({{"stand_defaults",
                     {{"rolls", {{"radius_mm", 250}}}, {"strip", {{"flow_stress_MPa", 420}}}}},
                    {"stands",
                     {json::object(),
                      json::object(),
                      {{"rolls", {{"radius_mm", 300}}}},
                      json::object(),
                      json::object()}}});
    REQUIRE(mill.size() == 5);
    for (int i = 0; i < 5; ++i) {
        CAPTURE(i);
        CHECK(mill.stands[static_cast<std::size_t>(i)].strip.flow_stress == 420e6);
        CHECK(mill.stands[static_cast<std::size_t>(i)].rolls.radius == (i == 2 ? 0.3 : 0.25));
    }
    // A null stand patch is the shared stand.
    const core::Mill nulls =
        read_clean({{"stand_defaults", {{"rolls", {{"radius_mm", 250}}}}},
                    {"stands", {nullptr, nullptr, nullptr, nullptr, nullptr}}});
    CHECK(nulls.stands[0].rolls.radius == 0.25);
}

TEST_CASE("a stand count other than 1 to 6 and lists of the wrong length are refused") {
    CHECK(has(pointers_of({{"stands", json::array()}}), "/tandem/stands"));
    CHECK(has(pointers_of({{"stands", json::array({{}, {}, {}, {}, {}, {}, {}})}}),
              "/tandem/stands"));
    const auto three = pointers_of({{"stands", json::array({{}, {}, {}})}});
    CHECK(has(three, "/tandem/exit_thickness_mm"));
    CHECK(has(three, "/tandem/spans/length_m"));
    CHECK(has(three, "/tandem/spans/tension_MPa"));
    // a consistent three-stand mill is a mill, one stand is too (no spans)
    const core::Mill small =
        read_clean({{"exit_thickness_mm", {2.25, 1.88, 1.6}},
                    {"spans", {{"length_m", {5, 5}}, {"tension_MPa", {60, 70}}}},
                    {"stands", json::array({{}, {}, {}})}});
    CHECK(small.size() == 3);
    CHECK(small.interstand_tension[1] == 70e6);
    const core::Mill one =
        read_clean({{"exit_thickness_mm", {2.25}},
                    {"spans", {{"length_m", json::array()}, {"tension_MPa", json::array()}}},
                    {"stands", json::array({json::object()})}});
    CHECK(one.size() == 1);
}

TEST_CASE("a thickness that grows downstream is a violation at that stand's exit thickness") {
    const auto pointers = pointers_of({{"exit_thickness_mm", {2.25, 1.88, 1.95, 1.36, 1.2}}});
    CHECK(has(pointers, "/tandem/exit_thickness_mm/2"));
    CHECK(pointers.size() == 1);
    // equal is not thinner either; the entry counts as stand 1's upstream
    CHECK(has(pointers_of({{"entry_thickness_mm", 2.25}}), "/tandem/exit_thickness_mm/0"));
}

TEST_CASE("what the mill gives a stand is refused in the stands' patches, with the field to use") {
    FieldErrors errors;
    (void)mill_from_patch({{"stand_defaults", {{"rolls", {{"speed_m_per_s", 10}}}}},
                           {"stands",
                            {json::object(),
                             {{"strip", {{"entry_thickness_mm", 2.0}, {"reduction", 0.2}}}},
                             {{"tension", {{"back", {{"stress_MPa", 50}}}}}},
                             json::object(),
                             json::object()}}},
                          "/tandem", errors);
    std::vector<std::string> pointers;
    for (const FieldError& error : errors.reported()) pointers.push_back(error.pointer);
    CHECK(has(pointers, "/tandem/stand_defaults/rolls/speed_m_per_s"));
    CHECK(has(pointers, "/tandem/stands/1/strip/entry_thickness_mm"));
    CHECK(has(pointers, "/tandem/stands/1/strip/reduction"));
    CHECK(has(pointers, "/tandem/stands/2/tension"));
    for (const FieldError& error : errors.reported())
        CHECK(error.detail.find("/tandem/") != std::string::npos);  // names where to set it
}

TEST_CASE("a stand's own violations carry its pointer, the mill's values are judged per stand") {
    // the example of the issue: stand 4's roll radius
    CHECK(has(pointers_of({{"stands",
                            {json::object(),
                             json::object(),
                             json::object(),
                             {{"rolls", {{"radius_mm", 5}}}},
                             json::object()}}}),
              "/tandem/stands/3/rolls/radius_mm"));
    // an interstand tension above a stand's flow stress: at the span's tension, naming the stand
    FieldErrors errors;
    (void)mill_from_patch({{"spans", {{"tension_MPa", {60, 60, 500, 60}}}}}, "/tandem", errors);
    REQUIRE(errors.size() == 1);
    CHECK(errors.reported()[0].pointer == "/tandem/spans/tension_MPa/2");
    CHECK(errors.reported()[0].detail.starts_with("stand 3: "));
    // the bite angle of a heavy pass on small rolls: at the exit thickness of that stand
    const auto heavy = pointers_of({{"exit_thickness_mm", {1.0, 0.9, 0.8, 0.7, 0.6}},
                                    {"stand_defaults", {{"rolls", {{"radius_mm", 10}}}}}});
    CHECK(has(heavy, "/tandem/exit_thickness_mm/0"));
}

TEST_CASE("a span at zero tension is slack: a violation unless the boundary is constant") {
    CHECK(has(pointers_of({{"exit", {{"tension_MPa", 0}}}}), "/tandem/exit/tension_MPa"));
    CHECK(has(pointers_of({{"entry", {{"tension_MPa", 0}}}}), "/tandem/entry/tension_MPa"));
    const core::Mill held = read_clean({{"exit", {{"boundary", "constant"}, {"tension_MPa", 0}}}});
    CHECK(held.exit == core::MillBoundary::constant);
    CHECK(held.exit_tension == 0.0);
    // an interstand span's tension is open at zero by its own bound
    CHECK(has(pointers_of({{"spans", {{"tension_MPa", {60, 0, 60, 60}}}}}),
              "/tandem/spans/tension_MPa/1"));
}

TEST_CASE("unknown members and wrong types are violations at their pointers, all at once") {
    const auto pointers = pointers_of(
        {{"mill", json::object()},
         {"speed_m_per_s", "fast"},
         {"spans", {{"length_m", 5}}},
         {"stands", {json::object(), 3, json::object(), json::object(), json::object()}}});
    CHECK(has(pointers, "/tandem/mill"));
    CHECK(has(pointers, "/tandem/speed_m_per_s"));
    CHECK(has(pointers, "/tandem/spans/length_m"));
    CHECK(has(pointers, "/tandem/stands/1"));
    CHECK(has(pointers_of(json::array()), "/tandem"));
}

TEST_CASE("the span model: spring by default, segments with its count, a count that is not whole") {
    const core::Mill spring = read_clean(json::object());
    CHECK(spring.span_model == core::SpanModel::spring);
    const core::Mill segments =
        read_clean(json{{"spans", {{"model", "segments"}, {"segment_count", 20}}}});
    CHECK(segments.span_model == core::SpanModel::segments);
    CHECK(segments.span_segments == 20);
    // the echo reruns to the same model, the count a whole number
    const json echo = resolved_tandem_json(segments);
    CHECK(echo["spans"]["model"] == "segments");
    CHECK(echo["spans"]["segment_count"].is_number_integer());
    FieldErrors errors;
    const core::Mill again = mill_from_json(echo, "/tandem", errors);
    CHECK(errors.empty());
    CHECK(again.span_segments == 20);
    // a fractional count, one below the bound and an unknown model: each at its pointer
    CHECK(has(pointers_of(json{{"spans", {{"segment_count", 10.5}}}}),
              "/tandem/spans/segment_count"));
    CHECK(has(pointers_of(json{{"spans", {{"segment_count", 1}}}}), "/tandem/spans/segment_count"));
    const std::vector<std::string> both =
        pointers_of(json{{"spans", {{"model", "strings"}, {"segment_count", 51}}}});
    CHECK(has(both, "/tandem/spans/model"));
    CHECK(has(both, "/tandem/spans/segment_count"));
}

TEST_CASE("speeds mode: every stand's roll speed in its patch, the mill speed the last one's") {
    const json speeds = {{"mode", "speeds"},
                         {"speed_m_per_s", 15.0},
                         {"stands",
                          {{{"rolls", {{"speed_m_per_s", 5.9}}}},
                           {{"rolls", {{"speed_m_per_s", 7.1}}}},
                           {{"rolls", {{"speed_m_per_s", 8.5}}}},
                           {{"rolls", {{"speed_m_per_s", 10.1}}}},
                           {{"rolls", {{"speed_m_per_s", 15.0}}}}}}};
    const core::Mill mill = read_clean(speeds);
    CHECK(mill.mode == core::MillMode::speeds);
    CHECK(mill.stands[1].rolls.speed == 7.1);
    CHECK(core::mill_roll_speeds(mill).back() == 15.0);
    // the echo keeps each stand's own speed and reads back to the same mill
    const json echo = resolved_tandem_json(mill);
    CHECK(echo["mode"] == "speeds");
    CHECK(echo["stands"][1]["rolls"]["speed_m_per_s"] == 7.1);
    FieldErrors errors;
    const core::Mill again = mill_from_json(echo, "/tandem", errors);
    CHECK(errors.empty());
    CHECK(again.stands[3].rolls.speed == 10.1);

    // every violation at once: two stands without a speed, and a mill speed that is not the
    // last stand's
    json broken = speeds;
    broken["speed_m_per_s"] = 14.0;
    broken["stands"][1] = json::object();
    broken["stands"][3]["rolls"] = json::object();
    const std::vector<std::string> pointers = pointers_of(broken);
    CHECK(has(pointers, "/tandem/stands/1/rolls/speed_m_per_s"));
    CHECK(has(pointers, "/tandem/stands/3/rolls/speed_m_per_s"));
    CHECK(has(pointers, "/tandem/speed_m_per_s"));
    CHECK(pointers.size() == 3);

    // schedule mode: a stand's roll speed is the mill's to give, a violation at the stand
    json schedule = speeds;
    schedule["mode"] = "schedule";
    const std::vector<std::string> refused = pointers_of(schedule);
    for (int i = 0; i < 5; ++i)
        CHECK(has(refused, "/tandem/stands/" + std::to_string(i) + "/rolls/speed_m_per_s"));
}
