// Asynchronous jobs over HTTP: 202 + Location, polling to a result, progress, cancel of queued
// and running jobs (the computation stops through Control), expiry after the retention, a
// bounded store (503 + Retry-After), validation of the envelope at creation.

#include "service/analyses/table.h"

#include <doctest/doctest.h>

#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace {

std::string create_job(httplib::Client& client, const json& request) {
    const std::string location = submit_job(client, request);
    CHECK(body_json(client.Get(location.c_str()))["instance"] == "test");
    return location;
}

}  // namespace

TEST_CASE("jobs over http: create, poll, the same result as the synchronous route") {
    TestServer server;
    auto client = server.client();
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    const std::string location = create_job(client, request);
    const json document = poll_until_finished(client, location);
    CHECK(document["state"] == "succeeded");
    CHECK(document["progress"] == 1.0);
    CHECK(document["result"] == service::evaluate(request).body);
    for (const char* stamp : {"created_at", "started_at", "finished_at", "expires_at"}) {
        CAPTURE(stamp);
        CHECK(document.contains(stamp));
    }
}

// Issue 17 (DECISIONS R): an invalid scenario is refused at submission (422, nothing stored);
// it was accepted with 202 and the job failed with the same problem when it ran.
TEST_CASE(
    "jobs over http: an invalid scenario or a bad envelope is refused at once, nothing stored") {
    TestServer server;
    auto client = server.client();
    const auto invalid =
        post_json(client, "/v1/jobs",
                  {{"analysis", "roll_gap"}, {"scenario", {{"strip", {{"reduction", 2}}}}}});
    REQUIRE(invalid);
    CHECK(invalid->status == 422);
    CHECK(invalid->get_header_value("Content-Type") == "application/problem+json");
    const json refused = json::parse(invalid->body);
    CHECK(refused["code"] == "invalid_scenario");
    CHECK(refused["errors"][0]["pointer"] == "/scenario/strip/reduction");

    const auto unknown = post_json(client, "/v1/jobs", {{"analysis", "rol_gap"}});
    REQUIRE(unknown);
    CHECK(unknown->status == 422);
    const json problem = json::parse(unknown->body);
    CHECK(problem["code"] == "unknown_analysis");
    CHECK(problem["errors"][0]["pointer"] == "/analysis");
    CHECK(problem["errors"][0]["detail"].get<std::string>().find("did you mean 'roll_gap'") !=
          std::string::npos);

    const auto no_analysis = post_json(client, "/v1/jobs", {{"scenario", json::object()}});
    REQUIRE(no_analysis);
    CHECK(no_analysis->status == 422);
    CHECK(json::parse(no_analysis->body)["code"] == "invalid_request");
    CHECK(server.server->job_counts().total() == 0);  // refused requests store nothing
}

TEST_CASE("jobs over http: progress while running, cancel stops the computation") {
    Gate gate;  // never opened: the job runs until cancelled
    TestServer server(test_config(), gate.evaluator());
    auto client = server.client();
    const std::string location = create_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    REQUIRE(eventually([&] {
        const json document = body_json(client.Get(location.c_str()));
        return document["state"] == "running" && document["progress"] == 0.5;
    }));

    const auto cancel = client.Delete(location.c_str());
    REQUIRE(cancel);
    CHECK(cancel->status == 200);  // one answer for every DELETE: the job after it
    CHECK(json::parse(cancel->body)["cancel_requested"] == true);
    CHECK(json::parse(cancel->body)["state"] == "running");
    const json document = poll_until_finished(client, location);
    CHECK(document["state"] == "cancelled");
    CHECK(gate.saw_cancel() == 1);
    CHECK(eventually([&] { return server.server->pool_stats().busy == 0; }));

    // A finished job is deleted by DELETE.
    const auto deleted = client.Delete(location.c_str());
    REQUIRE(deleted);
    CHECK(deleted->status == 200);
    CHECK(json::parse(deleted->body)["deleted"] == true);
    CHECK(json::parse(deleted->body)["state"] == "cancelled");
    const auto gone = client.Get(location.c_str());
    REQUIRE(gone);
    CHECK(gone->status == 404);
    CHECK(json::parse(gone->body)["code"] == "not_found");
}

TEST_CASE("jobs over http: a queued job is cancelled before it runs") {
    Gate gate;
    service::ServerConfig config = test_config();
    config.workers = 1;
    config.job_workers = 1;
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    const std::string running = create_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    const std::string queued = create_job(client, {{"analysis", "roll_gap"}});
    CHECK(body_json(client.Get(queued.c_str()))["state"] == "queued");
    const auto cancel = client.Delete(queued.c_str());
    REQUIRE(cancel);
    CHECK(cancel->status == 200);
    CHECK(json::parse(cancel->body)["state"] == "cancelled");
    gate.open();
    CHECK(poll_until_finished(client, running)["state"] == "succeeded");
    CHECK(eventually([&] {
        return server.server->pool_stats().busy == 0 &&
               server.server->pool_stats().batch_queued == 0;
    }));
    CHECK(gate.started() == 1);  // the cancelled job never ran
}

TEST_CASE(
    "jobs over http: DELETE of a queued job frees its slot: nine create/DELETE rounds with --max-jobs 4") {
    Gate gate;  // the first job runs until the end of the test
    service::ServerConfig config = test_config();
    config.workers = 2;
    config.job_workers = 1;
    config.max_jobs = 4;
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    const std::string running = create_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    for (int round = 0; round < 9; ++round) {
        CAPTURE(round);
        const std::string queued = create_job(client, {{"analysis", "roll_gap"}});
        const auto cancel = client.Delete(queued.c_str());
        REQUIRE(cancel);
        CHECK(cancel->status == 200);
        CHECK(server.server->job_counts().queued == 0);
        CHECK(server.server->pool_stats().batch_queued == 0);
    }
    gate.open();
    CHECK(poll_until_finished(client, running)["state"] == "succeeded");
    CHECK(poll_until_finished(client, create_job(client, {{"analysis", "roll_gap"}}))["state"] ==
          "succeeded");
    CHECK(gate.started() == 2);  // no cancelled job ran
}

TEST_CASE("jobs over http: the store is bounded (503 + Retry-After) and finished jobs expire") {
    Gate gate;  // the jobs run until it opens
    service::ServerConfig config = test_config();
    config.max_jobs = 2;
    config.job_retention = std::chrono::milliseconds(1500);
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    const std::string first = create_job(client, request);
    create_job(client, request);
    // two jobs queued or running: the third is refused
    const auto full = post_json(client, "/v1/jobs", request);
    REQUIRE(full);
    CHECK(full->status == 503);
    CHECK(full->get_header_value("Retry-After") == "1");
    CHECK(json::parse(full->body)["code"] == "overloaded");

    gate.open();
    CHECK(poll_until_finished(client, first)["state"] == "succeeded");
    // A finished job holds no slot: a new job is accepted while the first is still kept.
    const std::string third = create_job(client, request);
    CHECK(client.Get(first.c_str())->status == 200);
    // After the retention the job is gone.
    CHECK(eventually(
        [&] {
            const auto result = client.Get(first.c_str());
            return result && result->status == 404;
        },
        std::chrono::milliseconds(10'000)));
    CHECK(poll_until_finished(client, third)["state"] == "succeeded");
}

TEST_CASE("jobs over http: ids are not routes of their own") {
    TestServer server;
    auto client = server.client();
    const auto unknown = client.Get("/v1/jobs/0123456789abcdef0123456789abcdef");
    REQUIRE(unknown);
    CHECK(unknown->status == 404);
    const auto nested = client.Get("/v1/jobs/abc/result");
    REQUIRE(nested);
    CHECK(nested->status == 404);
    const auto cancel_unknown = client.Delete("/v1/jobs/nope");
    REQUIRE(cancel_unknown);
    CHECK(cancel_unknown->status == 404);
}

TEST_CASE(
    "jobs over http: a long job on the real facade reports progress and stops when cancelled") {
    REQUIRE(service::find_analysis(service::analyses(), "sweep") != nullptr);
    // A chunked job's progress counts finished points: small chunks finish the first soon,
    // also in the sanitizer build (a 25-point chunk took longer than the wait there).
    service::ServerConfig config = test_config();
    config.chunk_points = 5;
    TestServer server(config);
    auto client = server.client();
    const std::string location =
        create_job(client, {{"analysis", "sweep"},
                            {"options",
                             {{"parameter", "/lubricant/viscosity_Pa_s"},
                              {"range", {{"from", 0.0004}, {"to", 0.0008}, {"count", 300}}}}}});
    CHECK(eventually([&] {
        const json document = body_json(client.Get(location.c_str()));
        return document["state"] == "running" && document["progress"].get<double>() > 0.0;
    }));
    const auto cancel = client.Delete(location.c_str());
    REQUIRE(cancel);
    const auto start = std::chrono::steady_clock::now();
    CHECK(cancel->status == 200);
    const json document = poll_until_finished(client, location);
    CHECK(document["state"] == "cancelled");
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(2));
    // the points it finished stay readable: the cancelled sweep's partial result
    REQUIRE(document["points_done"].get<int>() > 0);
    REQUIRE(document.contains("partial_result"));
    const json& partial = document["partial_result"];
    CHECK(partial["points_done"] == document["points_done"]);
    CHECK(partial["points"].size() == document["points_done"].get<std::size_t>());
    CHECK(partial["points"][0]["point"].contains("critical_speed_m_per_s"));
}
