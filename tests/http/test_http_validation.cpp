// Requests are validated on the connection thread, before they are queued for a compute
// worker: a cheap 422 does not wait behind long computations. An empty body is the request {}.

#include "service/evaluate.h"

#include <doctest/doctest.h>

#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

TEST_CASE("validation: an invalid scenario is answered 422 at once while every worker is busy") {
    Gate gate;  // blocks each computation until opened
    service::ServerConfig config = test_config();
    config.workers = 1;
    config.deadline = std::chrono::milliseconds(4000);
    TestServer server(config, gate.evaluator());
    Background long_computation([&] {
        auto client = server.client();
        post_json(client, "/v1/roll-gap", json::object());
    });
    REQUIRE(eventually([&] { return gate.started() == 1; }));

    auto client = server.client();
    const auto start = std::chrono::steady_clock::now();
    const auto result =
        post_json(client, "/v1/roll-gap", {{"scenario", {{"strip", {{"reduction", 2}}}}}});
    const auto waited = std::chrono::steady_clock::now() - start;
    REQUIRE(result);
    CHECK(result->status == 422);
    const json problem = json::parse(result->body);
    CHECK(problem["code"] == "invalid_scenario");
    CHECK(problem["errors"][0]["pointer"] == "/scenario/strip/reduction");
    CHECK(waited < std::chrono::milliseconds(1000));
    CHECK(gate.started() == 1);  // the invalid request never reached the evaluator
    gate.open();
}

TEST_CASE("validation: an empty POST body is the request {} on the analysis routes") {
    TestServer server;
    auto client = server.client();
    json request = {{"analysis", "roll_gap"}};
    const json expected = service::evaluate(request).body;
    // Without a Content-Type, and with one.
    const auto bare = client.Post("/v1/roll-gap");
    REQUIRE(bare);
    CAPTURE(bare->body.substr(0, 300));
    CHECK(bare->status == 200);
    CHECK(json::parse(bare->body) == expected);
    const auto typed = client.Post("/v1/roll-gap", "", "application/json");
    REQUIRE(typed);
    CHECK(typed->status == 200);
    CHECK(json::parse(typed->body) == expected);
    // The jobs route needs its analysis named: {} is refused naming the field.
    const auto job = client.Post("/v1/jobs");
    REQUIRE(job);
    CHECK(job->status == 422);
    CHECK(json::parse(job->body)["code"] == "invalid_request");
}
