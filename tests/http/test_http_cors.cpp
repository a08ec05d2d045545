// CORS for a browser HMI on another origin, on a real server: the origins of --allowed-origins
// (none by default) are answered with Access-Control-Allow-Origin and the headers a page may
// read, a preflight is told the route's methods and the headers it may send; any other origin
// gets no CORS header and its unsafe requests stay refused (403); the answer varies by Origin.

#include <doctest/doctest.h>

#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace cors_test {

const std::string hmi = "http://hmi.plant.example:3000";

service::ServerConfig with_hmi() {
    service::ServerConfig config = test_config();
    config.allowed_origins = {hmi};
    return config;
}

}  // namespace cors_test

TEST_CASE("cors: a listed origin's preflight and request are answered for the browser") {
    TestServer server(cors_test::with_hmi());
    auto client = server.client();
    const auto preflight = client.Options(
        "/v1/stability", {{"Origin", cors_test::hmi},
                          {"Access-Control-Request-Method", "POST"},
                          {"Access-Control-Request-Headers", "content-type, authorization"}});
    REQUIRE(preflight);
    CHECK(preflight->status == 204);
    CHECK(preflight->get_header_value("Access-Control-Allow-Origin") == cors_test::hmi);
    CHECK(preflight->get_header_value("Access-Control-Allow-Methods").find("POST") !=
          std::string::npos);
    const std::string allowed = preflight->get_header_value("Access-Control-Allow-Headers");
    CHECK(allowed.find("Content-Type") != std::string::npos);
    CHECK(allowed.find("Authorization") != std::string::npos);
    CHECK(std::stoi(preflight->get_header_value("Access-Control-Max-Age")) > 0);

    const auto posted =
        post_json(client, "/v1/stability", {{"options", {{"critical_speed", false}}}},
                  {{"Origin", cors_test::hmi}});
    REQUIRE(posted);
    CHECK(posted->status == 200);
    CHECK(posted->get_header_value("Access-Control-Allow-Origin") == cors_test::hmi);
    CHECK(posted->get_header_value("Vary").find("Origin") != std::string::npos);
    CHECK(posted->get_header_value("Vary").find("Accept") != std::string::npos);
    // a job's Location is readable by the page
    const auto job =
        post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}}, {{"Origin", cors_test::hmi}});
    REQUIRE(job);
    CHECK(job->status == 202);
    CHECK(job->get_header_value("Access-Control-Expose-Headers").find("Location") !=
          std::string::npos);
    // a refusal is readable too: the page can show the problem
    const auto refused =
        post_json(client, "/v1/roll-gap", {{"scenario", {{"strip", {{"reduction", 25}}}}}},
                  {{"Origin", cors_test::hmi}});
    REQUIRE(refused);
    CHECK(refused->status == 422);
    CHECK(refused->get_header_value("Access-Control-Allow-Origin") == cors_test::hmi);
}

TEST_CASE("cors: an origin not listed gets no CORS header and its writes stay refused") {
    TestServer server(cors_test::with_hmi());
    auto client = server.client();
    const std::string other = "http://elsewhere.example";
    const auto preflight = client.Options(
        "/v1/stability", {{"Origin", other}, {"Access-Control-Request-Method", "POST"}});
    REQUIRE(preflight);
    CHECK_FALSE(preflight->has_header("Access-Control-Allow-Origin"));
    CHECK_FALSE(preflight->has_header("Access-Control-Allow-Methods"));
    const auto posted = post_json(client, "/v1/stability", json::object(), {{"Origin", other}});
    REQUIRE(posted);
    CHECK(posted->status == 403);
    CHECK(json::parse(posted->body)["code"] == "cross_site_request");
    CHECK_FALSE(posted->has_header("Access-Control-Allow-Origin"));
    CHECK(posted->get_header_value("Vary").find("Origin") != std::string::npos);
}

TEST_CASE("cors: without --allowed-origins no answer carries a CORS header") {
    TestServer server;
    auto client = server.client();
    const auto preflight = client.Options(
        "/v1/stability", {{"Origin", cors_test::hmi}, {"Access-Control-Request-Method", "POST"}});
    REQUIRE(preflight);
    CHECK(preflight->status == 204);
    CHECK_FALSE(preflight->has_header("Access-Control-Allow-Origin"));
    const auto got = client.Get("/v1/scenarios/default", {{"Origin", cors_test::hmi}});
    REQUIRE(got);
    CHECK(got->status == 200);
    CHECK_FALSE(got->has_header("Access-Control-Allow-Origin"));
    CHECK_FALSE(got->has_header("Vary"));
}
