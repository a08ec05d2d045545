// Sweeps and maps computed in chunks of points (service/chunked.h), as jobs spread them over
// replicas: whatever the chunking, the result assembled from the chunks' documents is
// byte-identical to evaluate()'s, including the chatter-type changes between neighbours that a
// chunk boundary separates; chunk ranges are checked; the partial result lists the finished
// points in index order, each once, typed by its schema.

#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/analyses/table.h"
#include "service/chunked.h"
#include "service/evaluate.h"
#include "api/problem.h"
#include "service/openapi.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

// Cheap searches (loose tolerance, a narrow speed range) around the crossings of rough strips:
// between strip roughness 8 and 8.5 um the mode that goes unstable first changes from the
// ~109 Hz gap mode (third octave) to the ~480 Hz work-roll mode (fifth octave), and the
// lubricant's viscosity moves it back (tests/service/test_map.cpp shows the same on a 2 × 2 grid).
const json cheap_search = {{"speed_min_m_per_s", 40},
                           {"speed_max_m_per_s", 46.3},
                           {"speed_step_m_per_s", 0.5},
                           {"relative_tolerance", 1e-3}};

// Six values: a type change between 8 and 8.5 um, and the last two stable up to 46.3 m/s (no
// crossing mode, so their null chatter types are no change).
json roughness_sweep() {
    return {{"analysis", "sweep"},
            {"options",
             {{"parameter", "/roughness/strip_rq_um"},
              {"values", {7.5, 8, 8.5, 9, 9.5, 10}},
              {"critical_speed", cheap_search}}}};
}

// Amplitude points at computed range values (7.5, 10, 12.5 between the ends), short windows.
json amplitude_sweep() {
    return {{"analysis", "sweep"},
            {"options",
             {{"parameter", "/rolls/speed_m_per_s"},
              {"range", {{"from", 5}, {"to", 15}, {"count", 5}}},
              {"quantity", "amplitude"},
              {"amplitude", {{"window_s", 0.1}, {"relative_tolerance", 1e-4}}}}}};
}

// 3 × 4 cells: the type changes along both the rows and the columns.
json roughness_viscosity_map() {
    json search = cheap_search;
    search["speed_min_m_per_s"] = 35;
    search["speed_max_m_per_s"] = 55;
    return {{"analysis", "map"},
            {"options",
             {{"parameters",
               {{{"parameter", "/roughness/strip_rq_um"}, {"values", {8, 8.5, 9}}},
                {{"parameter", "/lubricant/viscosity_Pa_s"},
                 {"values", {5e-4, 5.5e-4, 6e-4, 6.5e-4}}}}},
              {"critical_speed", search}}}};
}

// [begin, end) of consecutive chunks of `size` points (the last one shorter).
std::vector<std::pair<std::int64_t, std::int64_t>> chunks_of(std::int64_t total,
                                                             std::int64_t size) {
    std::vector<std::pair<std::int64_t, std::int64_t>> chunks;
    for (std::int64_t begin = 0; begin < total; begin += size)
        chunks.emplace_back(begin, std::min(total, begin + size));
    return chunks;
}

// Every chunk computed on its own and passed through text, as the job store keeps it; the
// documents concatenated in order. Each chunk's documents must be the entries of the whole
// run's `listed` (points or cells) at the same indices.
json computed_in_chunks(const json& request, std::int64_t total, std::int64_t size,
                        const json& listed) {
    json all = json::array();
    for (const auto& chunk : chunks_of(total, size)) {
        const std::int64_t begin = chunk.first, end = chunk.second;
        CAPTURE(begin);
        CAPTURE(end);
        const Outcome computed = evaluate_points(request, begin, end);
        REQUIRE_MESSAGE(computed.ok(), computed.body.dump());
        REQUIRE(computed.body.is_array());
        REQUIRE(static_cast<std::int64_t>(computed.body.size()) == end - begin);
        const json stored = json::parse(computed.body.dump());
        for (std::int64_t i = begin; i < end; ++i) {
            CHECK(stored[static_cast<std::size_t>(i - begin)] ==
                  listed[static_cast<std::size_t>(i)]);
            all.push_back(stored[static_cast<std::size_t>(i - begin)]);
        }
    }
    return all;
}

// The identity for chunk sizes 1, 2, 3 and the whole request; returns evaluate()'s answer.
Outcome check_chunked_equals_whole(const json& request, const std::string& listed_name,
                                   std::int64_t expected_points) {
    const Outcome whole = evaluate(request);
    REQUIRE_MESSAGE(whole.ok(), whole.body.dump());
    const auto total = chunkable_points(request);
    REQUIRE(total.has_value());
    CHECK(*total == expected_points);
    const json& listed = whole.body["result"][listed_name];
    REQUIRE(static_cast<std::int64_t>(listed.size()) == *total);
    for (const std::int64_t size : {std::int64_t{1}, std::int64_t{2}, std::int64_t{3}, *total}) {
        CAPTURE(size);
        const Outcome assembled =
            assemble_points(request, computed_in_chunks(request, *total, size, listed));
        REQUIRE_MESSAGE(assembled.ok(), assembled.body.dump());
        CHECK(assembled.http_status == whole.http_status);
        CHECK(assembled.body.dump() == whole.body.dump());
    }
    return whole;
}

}  // namespace

TEST_CASE(
    "a critical-speed sweep assembled from chunks of 1, 2, 3 and all points is evaluate()'s answer, its type change across a boundary included") {
    const Outcome whole = check_chunked_equals_whole(roughness_sweep(), "points", 6);
    // The change lies between points 1 and 2: a boundary of the chunkings by 1 and by 2, inside
    // a chunk of 3. So the neighbour comparison runs on points that different chunks computed.
    const json& changes = whole.body["result"]["chatter_type_changes"];
    REQUIRE(changes.size() == 1);
    CHECK(changes[0]["from"] == 8.0);
    CHECK(changes[0]["to"] == 8.5);
    CHECK(changes[0]["from_chatter_type"] == "third_octave");
    CHECK(changes[0]["to_chatter_type"] == "fifth_octave");
    CHECK(whole.body["result"]["points"][5]["status"] == "stable_in_range");
}

TEST_CASE("an amplitude sweep assembled from chunks is evaluate()'s answer") {
    const Outcome whole = check_chunked_equals_whole(amplitude_sweep(), "points", 5);
    CHECK_FALSE(whole.body["result"].contains("chatter_type_changes"));
}

TEST_CASE(
    "a 3 x 4 map assembled from chunks of 1, 2, 3 and all cells is evaluate()'s answer, changes along rows and columns included") {
    const Outcome whole = check_chunked_equals_whole(roughness_viscosity_map(), "cells", 12);
    const json& changes = whole.body["result"]["chatter_type_changes"];
    bool along_row = false, along_column = false;
    for (const json& change : changes) {
        along_row = along_row || change["from"][0] == change["to"][0];
        along_column = along_column || change["from"][1] == change["to"][1];
    }
    CHECK(along_row);
    CHECK(along_column);
}

TEST_CASE("the chatter-type changes are derived from the point documents, not carried by them") {
    // Whatever a point's document says is what the assembly compares: a chunk cannot hand its
    // neighbours a change it did not compute.
    const json request = roughness_sweep();
    const Outcome whole = evaluate(request);
    REQUIRE(whole.ok());
    json points = whole.body["result"]["points"];
    points[0]["chatter_type"] = "fifth_octave";
    const Outcome assembled = assemble_points(request, points);
    REQUIRE(assembled.ok());
    const json& changes = assembled.body["result"]["chatter_type_changes"];
    REQUIRE(changes.size() == 2);
    CHECK(changes[0]["from"] == 7.5);
    CHECK(changes[0]["from_chatter_type"] == "fifth_octave");
    CHECK(changes[0]["to_chatter_type"] == "third_octave");
    CHECK(changes[1]["from"] == 8.0);
}

TEST_CASE("chunk ranges outside the request's points are a problem naming the range") {
    const json request = roughness_sweep();
    for (const auto& [begin, end] :
         std::vector<std::pair<std::int64_t, std::int64_t>>{{3, 2}, {0, 7}, {-1, 2}, {7, 7}}) {
        const std::int64_t b = begin, e = end;
        CAPTURE(b);
        CAPTURE(e);
        const Outcome outcome = evaluate_points(request, b, e);
        REQUIRE_FALSE(outcome.ok());
        CHECK(outcome.problem == api::ProblemCode::invalid_request);
        CHECK(outcome.http_status ==
              api::make_problem(api::ProblemCode::invalid_request, "").http_status());
        CHECK(outcome.body["detail"].get<std::string>().find("[0, 6)") != std::string::npos);
    }
    // An empty chunk is no error: no documents.
    const Outcome empty = evaluate_points(request, 6, 6);
    REQUIRE(empty.ok());
    CHECK(empty.body == json::array());
    // Assembling needs exactly one document per point.
    const Outcome short_of_one = assemble_points(
        request, computed_in_chunks(request, 5, 5, evaluate(request).body["result"]["points"]));
    CHECK(short_of_one.problem == api::ProblemCode::invalid_request);
    CHECK(assemble_points(request, json::object()).problem == api::ProblemCode::invalid_request);
    CHECK(assemble_points(request, json::array({1, 2, 3, 4, 5, 6})).problem ==
          api::ProblemCode::invalid_request);
}

TEST_CASE("what does not split: other analyses and invalid requests, as evaluate() reports them") {
    const json stability = {{"analysis", "stability"}};
    CHECK_FALSE(chunkable_points(stability).has_value());
    CHECK_FALSE(chunkable_points({{"analysis", "roll_gap"}}).has_value());
    const Outcome points = evaluate_points(stability, 0, 1);
    CHECK(points.problem == api::ProblemCode::invalid_request);
    CHECK(assemble_points(stability, json::array()).problem == api::ProblemCode::invalid_request);

    json invalid = roughness_sweep();
    invalid["options"]["values"][2] = -1;  // a roughness below its bound
    CHECK_FALSE(chunkable_points(invalid).has_value());
    const Outcome refused = evaluate(invalid);
    REQUIRE_FALSE(refused.ok());
    const Outcome chunk = evaluate_points(invalid, 0, 1);
    CHECK(chunk.problem == refused.problem);
    CHECK(chunk.body == refused.body);
    CHECK(assemble_points(invalid, json::array()).body == refused.body);
    CHECK_FALSE(chunkable_points({{"analysis", "no_such_analysis"}}).has_value());
    CHECK_FALSE(chunkable_points(json::array()).has_value());
}

TEST_CASE("a chunk's Control: cancellation stops it, progress covers its points") {
    const json request = amplitude_sweep();
    core::Control stopped;
    stopped.cancelled = [] { return true; };
    const Outcome cancelled = evaluate_points(request, 0, 2, stopped);
    CHECK(cancelled.problem == api::ProblemCode::cancelled);

    // Stopped after its first point: the chunk is refused, not returned short.
    std::atomic<bool> stop{false};
    core::Control midway;
    midway.cancelled = [&stop] { return stop.load(); };
    midway.progress = [&stop](double) { stop = true; };
    midway.threads = 1;
    CHECK(evaluate_points(request, 1, 4, midway).problem == api::ProblemCode::cancelled);

    std::atomic<int> reports{0};
    std::atomic<double> largest{0.0};
    core::Control watched;
    watched.threads = 1;
    watched.progress = [&](double fraction) {
        ++reports;
        if (fraction > largest) largest = fraction;
    };
    REQUIRE(evaluate_points(request, 2, 4, watched).ok());
    CHECK(reports >= 2);
    CHECK(largest == 1.0);
}

TEST_CASE("the partial result lists the finished points in index order, each once") {
    const json a = json::array({{{"p", 0}}, {{"p", 1}}});
    const json b = json::array({{{"p", 4}}, {{"p", 5}}});
    const json c = json::array({{{"p", 2}}});
    // Finished out of order; the chunk [4, 6) twice (a re-run after a lost lease); one reaching
    // past the end; one that is not an array.
    const json partial = partial_result(6, {{4, b},
                                            {0, a},
                                            {4, b},
                                            {2, c},
                                            {5, json::array({{{"p", 5}}, {{"p", 6}}})},
                                            {3, json::object()}});
    CHECK(partial["partial"] == true);
    CHECK(partial["points_total"] == 6);
    CHECK(partial["points_done"] == 5);
    REQUIRE(partial["points"].size() == 5);
    std::vector<std::int64_t> indices;
    for (const json& entry : partial["points"]) {
        indices.push_back(entry["index"].get<std::int64_t>());
        CHECK(entry["point"]["p"] == entry["index"]);
    }
    CHECK(indices == std::vector<std::int64_t>{0, 1, 2, 4, 5});
    const json none = partial_result(12, {});
    CHECK(none["points_done"] == 0);
    CHECK(none["points"] == json::array());
}

TEST_CASE("the partial result's schema describes the documents it is given") {
    const json request = roughness_sweep();
    const Outcome chunk = evaluate_points(request, 1, 3);
    REQUIRE(chunk.ok());
    const json partial = partial_result(6, {{1, chunk.body}});
    const json schema = partial_result_schema();
    // The members: exactly the required ones, no others.
    std::vector<std::string> members, required;
    for (const auto& item : partial.items()) members.push_back(item.key());
    for (const json& name : schema["required"]) required.push_back(name.get<std::string>());
    std::sort(required.begin(), required.end());
    CHECK(members == required);
    CHECK(schema["additionalProperties"] == false);
    // The point is one of the result tables' components, which the OpenAPI document defines;
    // this chunk's points have exactly the members of the sweep point's component.
    const json components = openapi_document()["components"]["schemas"];
    const json& entry = schema["properties"]["points"]["items"];
    CHECK(entry["required"] == json{"index", "point"});
    const json& choices = entry["properties"]["point"]["oneOf"];
    // One choice per point component of every pointwise analysis (their rows say which).
    std::size_t point_components = 0;
    for (const Analysis& analysis : analyses())
        point_components += analysis.point_components.size();
    REQUIRE(choices.size() == point_components);
    for (const json& choice : choices) {
        const std::string ref = choice["$ref"].get<std::string>();
        CAPTURE(ref);
        REQUIRE(ref.starts_with("#/components/schemas/"));
        CHECK(components.contains(ref.substr(21)));
    }
    const json& sweep_point = components["SweepCriticalSpeedPoint"];
    for (const json& listed : partial["points"]) {
        for (const auto& member : listed["point"].items()) {
            CAPTURE(member.key());
            CHECK((sweep_point["properties"].contains(member.key()) || member.key() == "value_um"));
        }
        for (const json& name : sweep_point["required"])
            CHECK(listed["point"].contains(name.get<std::string>()));
    }
}
