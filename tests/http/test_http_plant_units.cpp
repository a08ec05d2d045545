// Plant units over HTTP, on a real server: a speed in m/min, a viscosity in mPa·s, a diameter
// give the same answer as the canonical members and are echoed canonical; a stored stand
// written in plant units is stored canonical, and a request patching it in plant units merges
// onto it (the alternate is rewritten before the base is merged under it); two forms of one
// member are one 422 naming both.

#include <doctest/doctest.h>

#include <set>
#include <string>

#include "support/approx.h"
#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace plant_units_http_test {

json answer(httplib::Client& client, const std::string& path, const json& body, int status = 200) {
    const auto result = post_json(client, path, body);
    REQUIRE(result);
    CAPTURE(result->body.substr(0, 600));
    REQUIRE(result->status == status);
    return json::parse(result->body);
}

}  // namespace plant_units_http_test

namespace puh = plant_units_http_test;

TEST_CASE("plant units over HTTP: the same answer as the canonical members, echoed canonical") {
    TestServer server;
    auto client = server.client();
    const json plant = puh::answer(client, "/v1/roll-gap",
                                   {{"scenario",
                                     {{"rolls", {{"speed_m_per_min", 900}, {"diameter_mm", 520}}},
                                      {"lubricant", {{"viscosity_mPa_s", 0.8}}}}}});
    const json si = puh::answer(client, "/v1/roll-gap",
                                {{"scenario",
                                  {{"rolls", {{"speed_m_per_s", 15}, {"radius_mm", 260}}},
                                   {"lubricant", {{"viscosity_Pa_s", 0.0008}}}}}});
    CHECK(plant == si);
    CHECK(plant["scenario"]["rolls"]["speed_m_per_s"] == 15.0);
    CHECK_FALSE(plant["scenario"]["rolls"].contains("speed_m_per_min"));

    const json refused = puh::answer(
        client, "/v1/stability",
        {{"scenario", {{"rolls", {{"speed_m_per_s", 15}, {"speed_m_per_min", 900}}}}}}, 422);
    std::set<std::string> pointers;
    for (const json& e : refused["errors"]) pointers.insert(e["pointer"].get<std::string>());
    CHECK(pointers == std::set<std::string>{"/scenario/rolls/speed_m_per_s",
                                            "/scenario/rolls/speed_m_per_min"});
    // the mill's speed in m/min
    const json mill = puh::answer(
        client, "/v1/tandem",
        {{"tandem", {{"speed_m_per_min", 720}}}, {"options", {{"critical_speed", false}}}});
    CHECK(mill["tandem"]["speed_m_per_s"] == 12.0);
}

TEST_CASE("plant units over HTTP: a stored stand in plant units, patched in plant units") {
    TestServer server;
    auto client = server.client();
    const auto put = client.Put(
        "/v1/scenarios/line-3",
        json{{"lubricant", {{"viscosity_mPa_s", 1.2}}}, {"rolls", {{"diameter_mm", 540}}}}.dump(),
        "application/json");
    REQUIRE(put);
    CAPTURE(put->body.substr(0, 600));
    REQUIRE(put->status == 201);
    const json stored = body_json(client.Get("/v1/scenarios/line-3"));
    CHECK(stored["lubricant"]["viscosity_Pa_s"] == 0.0012);
    CHECK(stored["rolls"]["radius_mm"] == 270.0);
    CHECK_FALSE(stored["rolls"].contains("diameter_mm"));
    // a request on the stored stand with its speed in m/min: merged onto the stored radius
    const json on_base =
        puh::answer(client, "/v1/roll-gap",
                    {{"base", "line-3"}, {"scenario", {{"rolls", {{"speed_m_per_min", 600}}}}}});
    CHECK(on_base["scenario"]["rolls"]["speed_m_per_s"] == 10.0);
    CHECK(on_base["scenario"]["rolls"]["radius_mm"] == 270.0);
    CHECK(on_base["scenario"]["lubricant"]["viscosity_Pa_s"] == 0.0012);
    // a job stores its request canonical
    const std::string location =
        submit_job(client, {{"analysis", "roll_gap"},
                            {"base", "line-3"},
                            {"scenario", {{"rolls", {{"speed_m_per_min", 600}}}}}});
    const json job = poll_until_finished(client, location);
    REQUIRE(job["state"] == "succeeded");
    CHECK(job["result"]["scenario"] == on_base["scenario"]);
    // PATCH in plant units
    httplib::Headers if_match = {{"If-Match", put->get_header_value("ETag")}};
    const auto patched = client.Patch("/v1/scenarios/line-3", if_match,
                                      json{{"rolls", {{"diameter_mm", 500}}}}.dump(),
                                      "application/merge-patch+json");
    REQUIRE(patched);
    CAPTURE(patched->body.substr(0, 600));
    CHECK(patched->status == 200);
    CHECK(body_json(client.Get("/v1/scenarios/line-3"))["rolls"]["radius_mm"] == 250.0);
    const auto both = client.Put("/v1/scenarios/line-4",
                                 json{{"rolls", {{"radius_mm", 250}, {"diameter_mm", 500}}}}.dump(),
                                 "application/json");
    REQUIRE(both);
    CHECK(both->status == 422);
    CHECK(client.Get("/v1/scenarios/line-4")->status == 404);  // nothing stored
}

TEST_CASE("plant units over HTTP: an atypical value is answered with a warning, a job's too") {
    TestServer server;
    auto client = server.client();
    // 90 meant as m/min: accepted as 90 m/s (never guessed), and said
    const json answered =
        puh::answer(client, "/v1/roll-gap", {{"scenario", {{"rolls", {{"speed_m_per_s", 90}}}}}});
    REQUIRE(answered.contains("warnings"));
    REQUIRE(answered["warnings"].size() == 1);
    CHECK(answered["warnings"][0]["pointer"] == "/scenario/rolls/speed_m_per_s");
    CHECK(answered["warnings"][0]["likely"]["key"] == "speed_m_per_min");
    CHECK(answered["scenario"]["rolls"]["speed_m_per_s"] == 90.0);
    // a typical request has none
    CHECK_FALSE(puh::answer(client, "/v1/roll-gap", json::object()).contains("warnings"));
    // 900 is beyond the bound: refused, with the unit that fits
    const json refused = puh::answer(client, "/v1/roll-gap",
                                     {{"scenario", {{"rolls", {{"speed_m_per_s", 900}}}}}}, 422);
    CHECK(refused["errors"][0]["detail"].get<std::string>().find("send it as speed_m_per_min") !=
          std::string::npos);
    // a job's result carries its warnings
    const std::string location = submit_job(
        client, {{"analysis", "roll_gap"}, {"scenario", {{"rolls", {{"radius_mm", 560}}}}}});
    const json job = poll_until_finished(client, location);
    REQUIRE(job["state"] == "succeeded");
    CHECK(job["result"]["warnings"][0]["likely"]["key"] == "diameter_mm");
}

TEST_CASE(
    "plant units over HTTP: a tension in kN over a stored stand's strip, echoed as the stress") {
    TestServer server;
    auto client = server.client();
    // the strip from the stored stand, the force from the request: converted after the merge
    const auto put =
        client.Put("/v1/scenarios/narrow",
                   json{{"strip", {{"width_mm", 1200}, {"entry_thickness_mm", 2.0}}}}.dump(),
                   "application/json");
    REQUIRE(put);
    REQUIRE(put->status == 201);
    const json forces = puh::answer(client, "/v1/roll-gap",
                                    {{"base", "narrow"},
                                     {"scenario", {{"tension", {{"back", {{"force_kN", 120}}}}}}},
                                     {"options", {{"distributions", false}}}});
    // 120 kN over 1.2 m × 2.0 mm
    CHECK(forces["scenario"]["tension"]["back"]["stress_MPa"].get<double>() ==
          approx(120e3 / (1.2 * 2.0e-3) / 1e6).epsilon(1e-14));
    CHECK_FALSE(forces["scenario"]["tension"]["back"].contains("force_kN"));
    // the same answer as the stress itself
    json stress_request = {{"base", "narrow"},
                           {"scenario", forces["scenario"]},
                           {"options", {{"distributions", false}}}};
    CHECK(puh::answer(client, "/v1/roll-gap", stress_request)["result"] == forces["result"]);
    // a stored stand in kN, patched with a stress: the patch's stress wins
    const auto patch = client.Patch(
        "/v1/scenarios/narrow", {{"If-Match", put->get_header_value("ETag")}},
        json{{"tension", {{"back", {{"force_kN", 96}}}}}}.dump(), "application/merge-patch+json");
    REQUIRE(patch);
    CAPTURE(patch->body.substr(0, 400));
    REQUIRE(patch->status == 200);
    const json on_force =
        puh::answer(client, "/v1/roll-gap",
                    {{"base", "narrow"},
                     {"scenario", {{"tension", {{"back", {{"stress_MPa", 33}}}}}}},
                     {"options", {{"distributions", false}}}});
    CHECK(on_force["scenario"]["tension"]["back"]["stress_MPa"] == 33.0);
    const json stored_force = puh::answer(
        client, "/v1/roll-gap", {{"base", "narrow"}, {"options", {{"distributions", false}}}});
    CHECK(stored_force["scenario"]["tension"]["back"]["stress_MPa"].get<double>() ==
          approx(96e3 / (1.2 * 2.0e-3) / 1e6).epsilon(1e-14));
}

TEST_CASE("plant units over HTTP: a CSV in plant units on request, a mistyped units a 422") {
    TestServer server;
    auto client = server.client();
    const json request = {
        {"options",
         {{"parameter", "/lubricant/viscosity_Pa_s"},
          {"values", {0.0004, 0.0007}},
          {"critical_speed", {{"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 35}}}}}};
    const httplib::Headers csv = {{"Accept", "text/csv"}};
    const auto si = client.Post("/v1/sweeps", csv, request.dump(), "application/json");
    const auto plant =
        client.Post("/v1/sweeps?units=plant", csv, request.dump(), "application/json");
    const auto answer = client.Post("/v1/sweeps?units=plant", request.dump(), "application/json");
    REQUIRE(si);
    REQUIRE(plant);
    REQUIRE(answer);
    CAPTURE(plant->body.substr(0, 400));
    REQUIRE(si->status == 200);
    REQUIRE(plant->status == 200);
    REQUIRE(answer->status == 200);
    CHECK(si->body.starts_with("value_Pa_s,status,critical_speed_m_per_s,"));
    CHECK(plant->body.starts_with("value_mPa_s,status,critical_speed_m_per_min,"));
    // the values in mPa.s (the decimal shifted) and the critical speeds in m/min (× 60) of the
    // JSON answer, which stays canonical whatever units says
    const json points = json::parse(answer->body)["result"]["points"];
    REQUIRE(points.size() == 2);
    std::size_t line = plant->body.find("\r\n") + 2;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const std::string row = plant->body.substr(line, plant->body.find("\r\n", line) - line);
        CAPTURE(row);
        CHECK(row.starts_with(i == 0 ? "0.4,found," : "0.7,found,"));
        const std::size_t speed_at = row.find(',', row.find(',') + 1) + 1;
        CHECK(std::stod(row.substr(speed_at)) ==
              approx(points[i]["critical_speed_m_per_s"].get<double>() * 60.0).epsilon(1e-15));
        line = plant->body.find("\r\n", line) + 2;
    }
    CHECK(points[0]["value_Pa_s"] == 0.0004);
    const auto mistyped =
        client.Post("/v1/sweeps?units=imperial", csv, request.dump(), "application/json");
    REQUIRE(mistyped);
    CHECK(mistyped->status == 422);
    CHECK(json::parse(mistyped->body)["errors"][0]["pointer"] == "/query/units");
}
