// Stored stands in a mill (docs/http-api.md, "Stored stands in a mill") with a real server and
// its SQLite store: a stand of the tandem document names a stored stand scenario
// ("/tandem/stands/i/base"), and the mill runs that stand — its own values, the stand's patch
// over them, the values the mill gives every stand the mill's — exactly as the same stand written
// out by hand; the echo carries {"name", "version"} and reruns to the same answer; a mill speed
// limit takes the calibrated stand's stored posterior while it still describes the stand; every
// name that cannot be used is one 422, and without the service the name is refused with what to
// send instead; a batch of mills resolves the names of its shared stands and of each item's own.
// Two-stand mills: about 3 s here.

#include <doctest/doctest.h>

#include <string>

#include "support/approx.h"
#include "support/http_test.h"
#include "support/mill_requests.h"

using namespace rollgap;
using nlohmann::json;

namespace stand_bases_http {

// The two-stand mill with `second` as stand 2's entry and a shared viscosity for both stands.
json mill_with(const json& second) {
    json tandem = test::two_stands;
    tandem["stand_defaults"] = {{"lubricant", {{"viscosity_Pa_s", 0.0005}}}};
    tandem["stands"] = json::array({json::object(), second});
    return tandem;
}

// Stand F2 as stored: its own viscosity, flow stress and roughness, and values a mill gives
// every stand (a reduction, a roll speed, tensions) that the mill must override.
const json stored_f2 = {{"lubricant", {{"viscosity_Pa_s", 0.0007}}},
                        {"strip", {{"flow_stress_MPa", 420}, {"reduction", 0.3}}},
                        {"roughness", {{"roll_rq_um", 0.9}}},
                        {"rolls", {{"speed_m_per_s", 9}}},
                        {"tension", {{"back", {{"stress_MPa", 30}}}}}};

json put_stand(httplib::Client& client, const std::string& name, const json& body) {
    const auto put = client.Put(("/v1/scenarios/" + name).c_str(), body.dump(), "application/json");
    REQUIRE(put);
    CAPTURE(put->body.substr(0, 400));
    REQUIRE(put->status == 201);
    return json::parse(put->body);
}

// F2 calibrated on one coil (its roll force): the stored stand keeps the flow stress's posterior
// (version 2).
void calibrate_f2(httplib::Client& client) {
    const json calibration = {
        {"options",
         {{"parameters", {{{"field", "/strip/flow_stress_MPa"}}}},
          {"observations",
           {{{"quantity", "roll_force_kN"}, {"value", 6400}, {"standard_uncertainty", 50}}}}}}};
    const auto calibrated = client.Post("/v1/scenarios/F2/calibrate", {{"If-Match", "\"1\""}},
                                        calibration.dump(), "application/json");
    REQUIRE(calibrated);
    CAPTURE(calibrated->body.substr(0, 400));
    REQUIRE(calibrated->status == 200);
}

// A two-stand mill speed limit's search over 5-30 m/s, without what to change.
const json search = {{"speed_min_m_per_s", 5},
                     {"speed_max_m_per_s", 30},
                     {"speed_step_m_per_s", 0.5},
                     {"relative_tolerance", 1e-8},
                     {"what_to_change", false}};

bool has_error_at(const json& problem, const std::string& pointer) {
    for (const json& e : problem["errors"])
        if (e["pointer"] == pointer) return true;
    return false;
}

}  // namespace stand_bases_http

namespace sbh = stand_bases_http;

TEST_CASE(
    "stored stands in a mill: a stand named by its stored scenario is that stand written out, "
    "the mill's values the mill's") {
    test::TestServer server;
    auto client = server.client();
    sbh::put_stand(client, "F2", sbh::stored_f2);
    // stand 2 is F2 with its own asperity factor over it
    const json based = test::body_json(test::post_json(
        client, "/v1/tandem",
        {{"tandem", sbh::mill_with({{"base", "F2"}, {"friction", {{"asperity_factor", 0.9}}}})}}));
    REQUIRE(based.contains("result"));
    const json& stand = based["tandem"]["stands"][1];
    CHECK(stand["base"] == json{{"name", "F2"}, {"version", 1}});
    CHECK(stand["lubricant"]["viscosity_Pa_s"] == 0.0007);  // the stand's, not stand_defaults'
    CHECK(stand["strip"]["flow_stress_MPa"] == 420);
    CHECK(stand["friction"]["asperity_factor"] == 0.9);
    CHECK(based["tandem"]["stands"][0]["lubricant"]["viscosity_Pa_s"] == 0.0005);
    CHECK_FALSE(based["tandem"]["stands"][0].contains("base"));
    // The same stand written out by hand (its own values only: the mill gives the rest) is the
    // same mill: every figure of the answer equal.
    const json by_hand = test::body_json(
        test::post_json(client, "/v1/tandem",
                        {{"tandem", sbh::mill_with({{"lubricant", {{"viscosity_Pa_s", 0.0007}}},
                                                    {"strip", {{"flow_stress_MPa", 420}}},
                                                    {"roughness", {{"roll_rq_um", 0.9}}},
                                                    {"friction", {{"asperity_factor", 0.9}}}})}}));
    REQUIRE(by_hand.contains("result"));
    // (so stand 2 rolls the schedule's 1.6 → 1.36 mm at the mill's speed, not F2's reduction of
    // 0.3 at 9 m/s: the hand-written stand has neither)
    CHECK(based["result"] == by_hand["result"]);
    // the echo reruns to the same answer; its {name, version} is the service's to write, so a
    // client sends the stand without it (as a request's own "base")
    json echoed = based["tandem"];
    const auto claimed = test::post_json(client, "/v1/tandem", {{"tandem", echoed}});
    REQUIRE(claimed);
    CHECK(claimed->status == 422);
    CHECK(sbh::has_error_at(json::parse(claimed->body), "/tandem/stands/1/base"));
    echoed["stands"][1].erase("base");
    const json again = test::body_json(test::post_json(client, "/v1/tandem", {{"tandem", echoed}}));
    CHECK(again["result"] == based["result"]);
    // and the facade, which reads a job's stored request, takes the resolved form as it is
    const json resolved = test::answer_of({{"analysis", "tandem"}, {"tandem", based["tandem"]}});
    CHECK(resolved["result"] == based["result"]);
    CHECK(resolved["tandem"]["stands"][1]["base"] == stand["base"]);
    // a job is resolved when it is accepted: its stored request holds the stand
    const std::string location = test::submit_job(
        client, {{"analysis", "tandem"}, {"tandem", sbh::mill_with({{"base", "F2"}})}});
    const json job = test::poll_until_finished(client, location, std::chrono::milliseconds(30000));
    REQUIRE(job["state"] == "succeeded");
    CHECK(job["result"]["tandem"]["stands"][1]["base"] == stand["base"]);
    CHECK(job["result"]["tandem"]["stands"][1]["strip"]["flow_stress_MPa"] == 420);
}

TEST_CASE("stored stands in a mill: a calibrated stand brings its posterior to the speed limit") {
    test::TestServer server;
    auto client = server.client();
    sbh::put_stand(client, "F2", sbh::stored_f2);
    sbh::calibrate_f2(client);
    const json& search = sbh::search;
    const json answer = test::body_json(
        test::post_json(client, "/v1/tandem/speed-limit",
                        {{"tandem", sbh::mill_with({{"base", "F2"}})}, {"options", search}}));
    REQUIRE(answer.contains("result"));
    CHECK(answer["tandem"]["stands"][1]["base"]["version"] == 2);
    const json& posteriors = answer["options"]["posteriors"];
    REQUIRE(posteriors.is_array());
    REQUIRE(posteriors.size() == 2);
    CHECK(posteriors[0].is_null());
    REQUIRE(posteriors[1].is_object());
    CHECK(posteriors[1]["parameters"][0]["field"] == "/strip/flow_stress_MPa");
    // centred on the stand the mill runs: the stored fitted value is the stand's
    CHECK(posteriors[1]["parameters"][0]["value"].get<double>() ==
          test::approx(answer["tandem"]["stands"][1]["strip"]["flow_stress_MPa"].get<double>())
              .epsilon(1e-12));
    const json& u = answer["result"]["uncertainty"];
    REQUIRE(u.is_object());
    CHECK(u["propagated"] == true);
    REQUIRE(u["parameters"].size() == 1);
    CHECK(u["parameters"][0]["stand"] == 2);
    // the patch moves the flow stress: the posterior no longer describes the stand, none is taken
    const json moved = test::body_json(test::post_json(
        client, "/v1/tandem/speed-limit",
        {{"tandem", sbh::mill_with({{"base", "F2"}, {"strip", {{"flow_stress_MPa", 400}}}})},
         {"options", search}}));
    REQUIRE(moved.contains("result"));
    CHECK(moved["options"]["posteriors"].is_null());
    CHECK(moved["result"]["uncertainty"].is_null());
    // posteriors given by the request are the request's
    json own = search;
    own["posteriors"] = {nullptr, nullptr};
    const json given = test::body_json(
        test::post_json(client, "/v1/tandem/speed-limit",
                        {{"tandem", sbh::mill_with({{"base", "F2"}})}, {"options", own}}));
    REQUIRE(given.contains("result"));
    CHECK(given["options"]["posteriors"] == json::array({nullptr, nullptr}));
    CHECK(given["result"]["uncertainty"]["parameters"].empty());
}

TEST_CASE("stored stands in a mill: every name the mill cannot use is one 422") {
    test::TestServer server;
    auto client = server.client();
    const auto mill = client.Put("/v1/mills/M1", json::object().dump(), "application/json");
    REQUIRE(mill);
    REQUIRE(mill->status == 201);
    json tandem = sbh::mill_with({{"base", "M1"}});  // a stored mill, not a stand
    tandem["stands"][0] = {{"base", "nowhere"}};
    const auto refused = test::post_json(client, "/v1/tandem", {{"tandem", tandem}});
    REQUIRE(refused);
    CHECK(refused->status == 422);
    const json problem = json::parse(refused->body);
    CAPTURE(problem.dump());
    CHECK(problem["errors"].size() == 2);
    CHECK(sbh::has_error_at(problem, "/tandem/stands/0/base"));
    CHECK(sbh::has_error_at(problem, "/tandem/stands/1/base"));
    // without the service (the CLI's facade) a name cannot be resolved: said, with what to send
    const json facade =
        test::refusal_of({{"analysis", "tandem"}, {"tandem", sbh::mill_with({{"base", "F2"}})}});
    CHECK(sbh::has_error_at(facade, "/tandem/stands/1/base"));
    CHECK(facade.dump().find("GET /v1/scenarios/F2") != std::string::npos);
}

TEST_CASE("stored stands in a mill: a batch of mills resolves its stands' names, shared and own") {
    test::TestServer server;
    auto client = server.client();
    sbh::put_stand(client, "F2", sbh::stored_f2);
    sbh::calibrate_f2(client);
    const json two_plain = json::array({json::object(), json::object()});
    const json moved =
        json::array({json::object(), {{"base", "F2"}, {"strip", {{"flow_stress_MPa", 400}}}}});
    json batch = {{"analysis", "tandem_speed_limit"},
                  {"options", sbh::search},
                  {"tandem", sbh::mill_with({{"base", "F2"}})},
                  {"items", json::array({
                                {{"label", "C-1"}},  // the batch's stands: F2, its posterior
                                {{"label", "C-2"}, {"tandem", {{"stands", two_plain}}}},
                                {{"label", "C-3"}, {"tandem", {{"stands", moved}}}},
                                {{"label", "C-4"}, {"tandem", {{"speed_m_per_s", 12}}}},
                            })}};
    const auto submitted = test::post_json(client, "/v1/batches", {{"options", batch}});
    REQUIRE(submitted);
    CAPTURE(submitted->body.substr(0, 600));
    REQUIRE(submitted->status == 202);
    const json job = test::poll_until_finished(client, submitted->get_header_value("Location"),
                                               std::chrono::milliseconds(60000));
    CAPTURE(job.dump().substr(0, 800));
    REQUIRE(job["state"] == "succeeded");
    const json& rows = job["result"]["result"]["items"];
    REQUIRE(rows.size() == 4);
    // C-1 is the single request's answer: the same σ from F2's stored posterior
    const json single = test::body_json(
        test::post_json(client, "/v1/tandem/speed-limit",
                        {{"tandem", sbh::mill_with({{"base", "F2"}})}, {"options", sbh::search}}));
    const json sd = single["result"]["uncertainty"]["standard_deviation_m_per_s"];
    REQUIRE(sd.is_number());
    CHECK(rows[0]["headline"]["critical_speed_sd_m_per_s"] == sd);
    CHECK(rows[0]["headline"]["advised_speed_m_per_s"] ==
          single["result"]["advised_speed_m_per_s"]);
    CHECK(
        rows[1]["headline"]["critical_speed_sd_m_per_s"].is_null());  // its own stands, none stored
    CHECK(rows[2]["headline"]["critical_speed_sd_m_per_s"].is_null());    // F2 moved: not described
    CHECK(rows[3]["headline"]["critical_speed_sd_m_per_s"].is_number());  // the batch's stands
    CHECK(rows[3]["headline"]["operating_speed_m_per_s"] == 12.0);
    // every name the batch cannot use, shared or an item's, is one 422
    batch["tandem"]["stands"][1]["base"] = "nowhere";
    batch["items"][2]["tandem"]["stands"][1]["base"] = "nowhere-either";
    const auto refused = test::post_json(client, "/v1/batches", {{"options", batch}});
    REQUIRE(refused);
    CHECK(refused->status == 422);
    const json problem = json::parse(refused->body);
    CAPTURE(problem.dump());
    CHECK(sbh::has_error_at(problem, "/options/tandem/stands/1/base"));
    CHECK(sbh::has_error_at(problem, "/options/items/2/tandem/stands/1/base"));
}
