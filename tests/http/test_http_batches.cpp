// Batches over HTTP (docs/http-api.md, "Batches") with a real server and its SQLite store:
// POST /v1/batches queues a job whose rows are the items' answers, with stored bases resolved
// when the batch is accepted (a calibrated stand's posterior reaching its speed limits), rows
// as CSV from the job, an unknown base refused for the whole batch with every item named,
// the batch's own body limit above the 1 MiB of every other route, and a batch cancelled.

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;

namespace batch_http {

// A coarse critical-speed search with the plant's force and power limits: milliseconds a coil.
json coil_options() {
    return {{"speed_min_m_per_s", 10},    {"speed_max_m_per_s", 30},   {"speed_step_m_per_s", 0.5},
            {"relative_tolerance", 1e-4}, {"max_roll_force_kN", 7000}, {"max_power_kW", 6000}};
}

// `count` coils at speeds 14, 14.1, …, m/s.
json coils(int count) {
    json items = json::array();
    for (int i = 0; i < count; ++i) {
        items.push_back({{"label", "C-" + std::to_string(1000 + i)},
                         {"scenario", {{"rolls", {{"speed_m_per_s", 14 + 0.1 * i}}}}}});
    }
    return items;
}

httplib::Result post_batch(httplib::Client& client, const json& options,
                           const httplib::Headers& headers = {}) {
    return post_json(client, "/v1/batches", {{"options", options}}, headers);
}

std::string accepted(const httplib::Result& result) {
    REQUIRE(result);
    CAPTURE(result->body.substr(0, 600));
    REQUIRE(result->status == 202);
    return result->get_header_value("Location");
}

}  // namespace batch_http

using namespace batch_http;

TEST_CASE(
    "batches over http: a job of coils whose rows are the items' answers, stored bases read once") {
    TestServer server;
    auto client = server.client();
    REQUIRE(client
                .Put("/v1/scenarios/stand-3", json{{"rolls", {{"speed_m_per_s", 17}}}}.dump(),
                     "application/json")
                ->status == 201);
    // Calibrated on one coil: the stored stand keeps the flow stress's posterior.
    const json calibration = {
        {"options",
         {{"parameters", {{{"field", "/strip/flow_stress_MPa"}}}},
          {"observations",
           {{{"quantity", "roll_force_kN"}, {"value", 6400}, {"standard_uncertainty", 50}}}}}}};
    const auto calibrated = client.Post("/v1/scenarios/stand-3/calibrate", {{"If-Match", "\"1\""}},
                                        calibration.dump(), "application/json");
    REQUIRE(calibrated);
    CAPTURE(calibrated->body.substr(0, 400));
    REQUIRE(calibrated->status == 200);

    json options = {{"analysis", "speed_limit"}, {"options", coil_options()}, {"items", coils(30)}};
    options["items"][4]["base"] = "stand-3";
    options["items"][4].erase("scenario");
    options["items"][5]["base"] = "stand-3";  // its flow stress moved: the posterior no longer fits
    options["items"][5]["scenario"] = {{"strip", {{"flow_stress_MPa", 380}}}};
    options["items"][6]["scenario"] = {{"strip", {{"reduction", 3}}}};
    const std::string location = accepted(post_batch(client, options));
    const json job = poll_until_finished(client, location, std::chrono::milliseconds(60000));
    CAPTURE(job.dump().substr(0, 800));
    REQUIRE(job["state"] == "succeeded");
    CHECK(job["analysis"] == "batch");
    CHECK(job["points_total"] == 30);
    const json& result = job["result"]["result"];
    CHECK(result["succeeded"] == 29);
    CHECK(result["failed"] == 1);
    const json& rows = result["items"];
    REQUIRE(rows.size() == 30);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        CAPTURE(i);
        CHECK(rows[i]["index"] == i);
        CHECK(rows[i]["label"] == options["items"][i]["label"]);
    }
    // Each row is the answer its request gives on its own, through the same server.
    for (const std::size_t i : {0U, 13U, 29U}) {
        CAPTURE(i);
        json own = {{"scenario", options["items"][i]["scenario"]}, {"options", coil_options()}};
        own["options"]["what_to_change"] = false;
        const json alone = body_json(post_json(client, "/v1/speed-limit", own));
        CHECK(rows[i]["headline"]["advised_speed_m_per_s"] ==
              alone["result"]["advised_speed_m_per_s"]);
        CHECK(rows[i]["headline"]["operating_speed_m_per_s"] ==
              alone["result"]["operating_speed_m_per_s"]);
    }
    // The stored stand, the version read when the batch was accepted, with its uncertainty.
    CHECK(rows[4]["base"] == json{{"name", "stand-3"}, {"version", 2}});
    CHECK(rows[4]["headline"]["operating_speed_m_per_s"] == 17.0);
    CHECK(rows[4]["headline"]["critical_speed_sd_m_per_s"].get<double>() > 0.0);
    CHECK(rows[5]["base"] == json{{"name", "stand-3"}, {"version", 2}});
    CHECK(rows[5]["headline"]["critical_speed_sd_m_per_s"].is_null());
    CHECK(rows[6]["status"] == "failed");
    CHECK(rows[6]["problem"]["errors"][0]["pointer"] ==
          "/options/items/6/scenario/strip/reduction");

    // The rows as a sheet, from the job.
    const auto csv = client.Get(location.c_str(), {{"Accept", "text/csv"}});
    REQUIRE(csv);
    CHECK(csv->status == 200);
    CHECK(csv->get_header_value("Content-Type").starts_with("text/csv"));
    std::size_t lines = 0;
    for (std::size_t at = csv->body.find("\r\n"); at != std::string::npos;
         at = csv->body.find("\r\n", at + 2))
        ++lines;
    CHECK(lines == 31);
    CHECK(csv->body.starts_with("index,label,status,base_name,base_version,"));
    CHECK(csv->body.find("\r\n4,C-1004,ok,stand-3,2,") != std::string::npos);

    // The batch's own base for every item without one.
    json shared = {{"analysis", "speed_limit"},
                   {"base", "stand-3"},
                   {"options", coil_options()},
                   {"items", {{{"label", "a"}}, {{"label", "b"}}}}};
    const json second = poll_until_finished(client, accepted(post_batch(client, shared)),
                                            std::chrono::milliseconds(30000));
    REQUIRE(second["state"] == "succeeded");
    for (const json& row : second["result"]["result"]["items"]) {
        CHECK(row["base"]["name"] == "stand-3");
        CHECK(row["headline"]["operating_speed_m_per_s"] == 17.0);
    }
}

TEST_CASE(
    "batches over http: an unknown base refuses the batch, every such item named, nothing stored") {
    TestServer server;
    auto client = server.client();
    json options = {{"analysis", "speed_limit"}, {"options", coil_options()}, {"items", coils(5)}};
    options["items"][1]["base"] = "no-such-stand";
    options["items"][3]["base"] = "also-missing";
    options["items"][4]["base"] = "bad name!";
    const auto refused = post_batch(client, options);
    REQUIRE(refused);
    CAPTURE(refused->body);
    CHECK(refused->status == 422);
    const json problem = json::parse(refused->body);
    std::vector<std::string> pointers;
    for (const json& error : problem["errors"]) pointers.push_back(error["pointer"]);
    CHECK(pointers == std::vector<std::string>{"/options/items/1/base", "/options/items/3/base",
                                               "/options/items/4/base"});
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].empty());

    // The shape of the batch is the batch's 422 too, before anything is stored.
    const auto shapeless =
        post_batch(client, {{"analysis", "speed_limit"}, {"items", json::array()}});
    REQUIRE(shapeless);
    CHECK(shapeless->status == 422);
    CHECK(json::parse(shapeless->body)["errors"][0]["pointer"] == "/options/items");
    // More items than a batch takes: refused for its count, no base of its items looked up.
    json many = {{"analysis", "speed_limit"}, {"items", coils(10001)}};
    for (json& item : many["items"]) item["base"] = "no-such-stand";
    const auto oversized = post_batch(client, many);
    REQUIRE(oversized);
    CHECK(oversized->status == 422);
    const json count_problem = json::parse(oversized->body);
    CHECK(count_problem["errors"].size() == 1);
    CHECK(count_problem["errors"][0]["pointer"] == "/options/items");
    // The route names its analysis.
    const auto named =
        post_json(client, "/v1/batches", {{"analysis", "batch"}, {"options", options}});
    REQUIRE(named);
    CHECK(named->status == 422);
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].empty());
}

TEST_CASE("batches over http: the batch route's own body limit, above every other route's 1 MiB") {
    service::ServerConfig config = test_config();
    config.max_batch_body_bytes = 3 * 1024 * 1024;
    TestServer server(config);
    auto client = server.client();
    // ~1.15 MB: 1,000 roll gaps, each patch the whole default stand (as an MES sends a full
    // document per coil).
    const json stand = body_json(client.Get("/v1/scenarios/default"));
    json items = json::array();
    for (int i = 0; i < 1000; ++i)
        items.push_back({{"label", "coil " + std::to_string(i)}, {"scenario", stand}});
    const json options = {{"analysis", "roll_gap"}, {"items", items}};
    const std::string body = json{{"options", options}}.dump();
    REQUIRE(body.size() > config.max_body_bytes);

    const auto batch = client.Post("/v1/batches", body, "application/json");
    const std::string location = accepted(batch);
    // The same size to POST /v1/jobs: that route keeps the 1 MiB limit, refused before the
    // body is read (declared length, nothing sent).
    const auto declared = [&](const std::string& path, std::size_t length) {
        return raw_exchange(server.port(), "POST " + path +
                                               " HTTP/1.1\r\nHost: t\r\nContent-Type: "
                                               "application/json\r\nContent-Length: " +
                                               std::to_string(length) + "\r\n\r\n{");
    };
    const std::string as_job = declared("/v1/jobs", body.size());
    CHECK(raw_status(as_job) == 413);
    CHECK(as_job.find(std::to_string(config.max_body_bytes)) != std::string::npos);
    // Beyond the batch's own limit: 413 naming it.
    const std::string too_large = declared("/v1/batches", config.max_batch_body_bytes + 1);
    CHECK(raw_status(too_large) == 413);
    CHECK(too_large.find(std::to_string(config.max_batch_body_bytes)) != std::string::npos);

    // DELETE, 200 and the job after it: a queued batch is cancelled, a running one stops within
    // one item of each chunk (then cancelled), a finished one is deleted (then gone).
    const auto deleted = client.Delete(location.c_str());
    REQUIRE(deleted);
    REQUIRE(deleted->status == 200);
    if (json::parse(deleted->body).value("deleted", false)) {
        CHECK(client.Get(location.c_str())->status == 404);
    } else {
        const json ended = poll_until_finished(client, location, std::chrono::milliseconds(30000));
        CHECK(ended["state"] == "cancelled");
        CHECK_FALSE(ended.contains("result"));
    }
}
