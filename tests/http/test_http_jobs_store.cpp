// Jobs in the durable store, over HTTP with real servers on loopback, each with a fresh SQLite
// store: jobs survive a restart (a finished one is served, a queued one runs), a drained
// replica gives its work back, the Idempotency-Key, pagination of GET /v1/jobs, DELETE reaching
// a worker of another server through the store, and a store that is unavailable and comes back.

#include "service/chunked.h"
#include "service/evaluate.h"
#include "service/store/job_store.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/http_test.h"
#include "support/approx.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace {

// Routes requests that ask for distributions to `gated`, the rest to the facade.
service::Evaluator gated_when_distributions(Gate& gate) {
    return [gated = gate.evaluator(), facade = service::facade_evaluator()](
               const json& request, const core::Control& control) {
        const bool hold =
            request.contains("options") && request["options"].value("distributions", false);
        return hold ? gated(request, control) : facade(request, control);
    };
}

std::vector<std::string> page_ids(const json& page) {
    std::vector<std::string> ids;
    for (const json& job : page["jobs"]) ids.push_back(job["id"]);
    return ids;
}

// Once the store is back, a submission is accepted (within the handle's retry interval) and
// runs, and the metric says the store is up.
void resume_jobs(TestServer& server, httplib::Client& client, const json& request) {
    std::string location;
    REQUIRE(eventually(
        [&] {
            const auto result = post_json(client, "/v1/jobs", request);
            if (!result || result->status != 202) return false;
            location = result->get_header_value("Location");
            return true;
        },
        std::chrono::milliseconds(10000)));
    CHECK(poll_until_finished(client, location)["state"] == "succeeded");
    CHECK(server.server->metrics_text().find("rollgap_store_up 1") != std::string::npos);
}

}  // namespace

TEST_CASE(
    "durable jobs: a finished and a queued job survive a restart and the queued one then runs") {
    Gate gate;  // never opened: A holds the gated job until its drain gives it back
    service::ServerConfig config = test_config();
    config.workers = 2;
    config.job_workers = 1;
    config.drain_timeout = std::chrono::milliseconds(300);
    const json quick = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    const json held = {{"analysis", "roll_gap"}, {"options", {{"distributions", true}}}};

    std::string finished, running, queued;
    {
        config.instance = "replica-a";
        TestServer a(config, gated_when_distributions(gate));
        auto client = a.client();
        finished = submit_job(client, quick);
        REQUIRE(poll_until_finished(client, finished)["state"] == "succeeded");
        running = submit_job(client, held);
        REQUIRE(eventually([&] { return gate.started() == 1; }));
        queued = submit_job(client, quick);
        CHECK(body_json(client.Get(queued.c_str()))["state"] == "queued");
        a.server->shutdown();
        // The running item stopped at the drain timeout and went back to the store.
        CHECK(gate.saw_cancel() == 1);
        CHECK(a.server->metrics_text().find("rollgap_work_items_total{outcome=\"released\"} 1") !=
              std::string::npos);
    }
    config.instance = "replica-b";
    TestServer b(config);
    auto client = b.client();
    const json first = body_json(client.Get(finished.c_str()));
    CHECK(first["state"] == "succeeded");
    CHECK(first["instance"] == "replica-a");
    CHECK(first["result"] == service::evaluate(quick).body);
    const json after_queued = poll_until_finished(client, queued);
    CHECK(after_queued["state"] == "succeeded");
    CHECK(after_queued["result"] == service::evaluate(quick).body);
    CHECK(after_queued["worker"] == "replica-b");
    const json after_running = poll_until_finished(client, running);
    CHECK(after_running["state"] == "succeeded");
    CHECK(after_running["instance"] == "replica-a");
    CHECK(after_running["worker"] == "replica-b");
    CHECK(after_running["result"] == service::evaluate(held).body);
}

TEST_CASE("durable jobs: the Idempotency-Key returns the same job and another body is a 409") {
    TestServer server;
    auto client = server.client();
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    const httplib::Headers key = {{"Idempotency-Key", "order-4711/retry"}};
    const auto first = post_json(client, "/v1/jobs", request, key);
    REQUIRE(first);
    REQUIRE(first->status == 202);
    const std::string id = json::parse(first->body)["id"];
    // The same body with its keys in another order is the same request.
    const auto again = client.Post(
        "/v1/jobs", key, R"({"options": {"distributions": false}, "analysis": "roll_gap"})",
        "application/json");
    REQUIRE(again);
    CHECK(again->status == 200);
    CHECK(json::parse(again->body)["id"] == id);
    CHECK(again->get_header_value("Location") == "/v1/jobs/" + id);

    json other = request;
    other["options"]["distributions"] = true;
    const auto conflict = post_json(client, "/v1/jobs", other, key);
    REQUIRE(conflict);
    CHECK(conflict->status == 409);
    CHECK(json::parse(conflict->body)["code"] == "conflict");

    const auto blank = post_json(client, "/v1/jobs", request, {{"Idempotency-Key", "a b"}});
    REQUIRE(blank);
    CHECK(blank->status == 422);
    CHECK(json::parse(blank->body)["code"] == "invalid_request");
    const auto long_key =
        post_json(client, "/v1/jobs", request, {{"Idempotency-Key", std::string(201, 'k')}});
    REQUIRE(long_key);
    CHECK(long_key->status == 422);
    CHECK(server.server->job_counts().total() == 1);

    // Without a key every submission is a job of its own.
    submit_job(client, request);
    CHECK(server.server->job_counts().total() == 2);
}

TEST_CASE(
    "durable jobs: GET /v1/jobs lists newest first and the cursor walks all and the state filters") {
    Gate gate;
    service::ServerConfig config = test_config();
    config.workers = 2;
    config.job_workers = 1;
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    std::vector<std::string> created;
    for (int i = 0; i < 5; ++i) {
        const std::string location = submit_job(client, {{"analysis", "roll_gap"}});
        created.push_back(location.substr(std::string("/v1/jobs/").size()));
        if (i == 0) REQUIRE(eventually([&] { return gate.started() == 1; }));
    }
    std::vector<std::string> walked;
    std::string path = "/v1/jobs?limit=2";
    for (int page = 0; page < 5; ++page) {
        const json body = body_json(client.Get(path.c_str()));
        const auto ids = page_ids(body);
        CHECK(ids.size() <= 2);
        walked.insert(walked.end(), ids.begin(), ids.end());
        for (const json& job : body["jobs"]) CHECK_FALSE(job.contains("result"));
        if (!body.contains("next_cursor")) break;
        path = "/v1/jobs?limit=2&cursor=" + body["next_cursor"].get<std::string>();
    }
    const std::vector<std::string> newest_first(created.rbegin(), created.rend());
    CHECK(walked == newest_first);

    const json running = body_json(client.Get("/v1/jobs?state=running"));
    CHECK(page_ids(running) == std::vector<std::string>{created.front()});
    const json queued = body_json(client.Get("/v1/jobs?state=queued"));
    CHECK(page_ids(queued) ==
          std::vector<std::string>(newest_first.begin(), newest_first.end() - 1));
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].size() == 5);  // default page: 20

    for (const char* bad : {"limit=0", "limit=101", "limit=ten", "state=done", "cursor=x1"}) {
        CAPTURE(bad);
        const auto refused = client.Get((std::string("/v1/jobs?") + bad).c_str());
        REQUIRE(refused);
        CHECK(refused->status == 422);
        const json problem = json::parse(refused->body);
        CHECK(problem["code"] == "invalid_request");
        const std::string name = std::string(bad).substr(0, std::string(bad).find('='));
        CHECK(problem["detail"].get<std::string>().find("'" + name + "'") != std::string::npos);
        REQUIRE(problem["errors"].size() == 1);
        CHECK(problem["errors"][0]["pointer"] == "/query/" + name);
        CHECK(problem["errors"][0].contains("bound"));
    }
    gate.open();
}

TEST_CASE("durable jobs: DELETE on one server reaches the worker of another through the store") {
    Gate gate;  // never opened: only the cancel ends the computation
    service::ServerConfig config = test_config();
    config.lease = std::chrono::milliseconds(600);  // renewed every 200 ms
    config.instance = "replica-a";
    TestServer a(config, gate.evaluator());
    auto client_a = a.client();
    const std::string location = submit_job(client_a, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));

    config.instance = "replica-b";
    TestServer b(config);
    auto client_b = b.client();
    const json seen = body_json(client_b.Get(location.c_str()));
    CHECK(seen["state"] == "running");
    CHECK(seen["instance"] == "replica-a");
    CHECK(seen["worker"] == "replica-a");
    const auto cancel = client_b.Delete(location.c_str());
    REQUIRE(cancel);
    CHECK(cancel->status == 200);
    CHECK(json::parse(cancel->body)["cancel_requested"] == true);
    const json document = poll_until_finished(client_b, location);
    CHECK(document["state"] == "cancelled");
    CHECK(gate.saw_cancel() == 1);
    // replica a's worker counts the item after it has written the job's end to the store, which
    // replica b may read first: the count is awaited, not raced (a run under the sanitizers lost
    // that race once)
    CHECK(eventually([&] {
        return a.server->metrics_text().find("rollgap_work_items_total{outcome=\"cancelled\"} 1") !=
               std::string::npos;
    }));
}

TEST_CASE(
    "durable jobs: an unavailable store stops jobs only (503 store_unavailable) and service resumes when it is back") {
    // A data directory that cannot be created: its path is a regular file (chmod would not stop
    // root, who runs CI).
    const std::filesystem::path blocker = std::filesystem::path(fresh_temp_dir()) / "data";
    std::ofstream(blocker) << "not a directory";
    service::ServerConfig config = test_config();
    config.data_dir = blocker.string();
    config.store = "sqlite:" + (blocker / "jobs.db").string();
    TestServer server(config);
    auto client = server.client();
    httplib::Client admin("127.0.0.1", server.server->admin_port());
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};

    const auto sync = post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}});
    REQUIRE(sync);
    CHECK(sync->status == 200);
    const auto ready = admin.Get("/readyz");
    REQUIRE(ready);
    CHECK(ready->status == 200);
    for (int attempt = 0; attempt < 2; ++attempt) {
        const auto refused = post_json(client, "/v1/jobs", request);
        REQUIRE(refused);
        CHECK(refused->status == 503);
        CHECK(refused->get_header_value("Retry-After") == "1");
        CHECK(json::parse(refused->body)["code"] == "store_unavailable");
    }
    const auto poll = client.Get("/v1/jobs/0123456789abcdef0123456789abcdef");
    REQUIRE(poll);
    CHECK(poll->status == 503);
    CHECK(server.server->metrics_text().find("rollgap_store_up 0") != std::string::npos);

    std::filesystem::remove(blocker);
    std::filesystem::create_directory(blocker);
    resume_jobs(server, client, request);
    // The refused submissions left nothing behind.
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].size() == 1);
}

namespace {

const json five_point_sweep = {{"analysis", "sweep"},
                               {"options",
                                {{"parameter", "/lubricant/viscosity_Pa_s"},
                                 {"values", {0.0004, 0.0005, 0.0006, 0.0007, 0.0008}}}}};

}  // namespace

TEST_CASE("durable jobs: a sweep computed in chunks is assembled into the single-process result") {
    service::ServerConfig config = test_config();
    config.chunk_points = 2;  // chunks [0, 2), [2, 4), [4, 5)
    TestServer server(config);
    auto client = server.client();
    const std::string location = submit_job(client, five_point_sweep);
    const json document = poll_until_finished(client, location, std::chrono::milliseconds(60000));
    CHECK(document["state"] == "succeeded");
    CHECK(document["points_total"] == 5);
    CHECK(document["points_done"] == 5);
    CHECK(document["progress"] == 1.0);
    CHECK_FALSE(document.contains("partial_result"));
    CHECK(document["result"].dump() == service::evaluate(five_point_sweep).body.dump());
    CHECK(server.server->metrics_text().find("rollgap_work_items_total{outcome=\"succeeded\"} 3") !=
          std::string::npos);
}

TEST_CASE("durable jobs: a running chunked job shows its finished points as a partial result") {
    service::ServerConfig config = test_config();
    // Another replica, played by the test on the same store, created the job, holds all three
    // chunks and finished the first.
    auto opened = service::store::open_store(config.store);
    REQUIRE(opened.ok());
    auto& store = **opened.value;
    service::store::NewJob job;
    job.analysis = "sweep";
    job.request = five_point_sweep.dump();
    job.deadline_ms = service::store::system_millis() + 60'000;
    job.instance = "replica-test";
    job.points = 5;
    job.chunk_size = 2;
    const auto created = store.create(job);
    REQUIRE(created.ok());
    const std::string location = "/v1/jobs/" + created.value->job.id;
    std::vector<service::store::WorkItem> items;
    for (int i = 0; i < 3; ++i) {
        auto claimed = store.claim("replica-test", std::chrono::seconds(60));
        REQUIRE(claimed.ok());
        REQUIRE(claimed.value->has_value());
        items.push_back(**claimed.value);
    }
    REQUIRE(items.front().begin == 0);
    const auto first = service::evaluate_points(five_point_sweep, items[0].begin, items[0].end);
    REQUIRE(first.ok());
    REQUIRE(store.complete(items[0].lease, service::store::FinalState::succeeded, first.body.dump())
                .ok());

    TestServer server(config);
    auto client = server.client();
    const json document = body_json(client.Get(location.c_str()));
    CHECK(document["state"] == "running");
    CHECK(document["worker"] == "replica-test");
    CHECK(document["points_total"] == 5);
    CHECK(document["points_done"] == 2);
    CHECK(document["progress"] == rollgap::test::approx(0.4));
    const json& partial = document["partial_result"];
    CHECK(partial["partial"] == true);
    CHECK(partial["points_total"] == 5);
    CHECK(partial["points_done"] == 2);
    REQUIRE(partial["points"].size() == 2);
    const json whole = service::evaluate(five_point_sweep).body;
    for (int i = 0; i < 2; ++i) {
        CAPTURE(i);
        CHECK(partial["points"][i]["index"] == i);
        CHECK(partial["points"][i]["point"] == whole["result"]["points"][i]);
    }
    CHECK_FALSE(document.contains("result"));
}

TEST_CASE(
    "durable jobs (postgresql): a stopped database stops jobs only and service resumes when it is back") {
    PostgresServer postgres;
    REQUIRE_MESSAGE(postgres.running(), postgres.error());
    service::ServerConfig config = test_config();
    config.store = postgres.create_database("jobs_http");
    REQUIRE(!config.store.empty());
    TestServer server(config);
    auto client = server.client();
    httplib::Client admin("127.0.0.1", server.server->admin_port());
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    const std::string done = submit_job(client, request);
    REQUIRE(poll_until_finished(client, done)["state"] == "succeeded");

    REQUIRE(postgres.stop());
    const auto sync = post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}});
    REQUIRE(sync);
    CHECK(sync->status == 200);
    const auto ready = admin.Get("/readyz");
    REQUIRE(ready);
    CHECK(ready->status == 200);
    const auto refused = post_json(client, "/v1/jobs", request);
    REQUIRE(refused);
    CHECK(refused->status == 503);
    CHECK(refused->get_header_value("Retry-After") == "1");
    CHECK(json::parse(refused->body)["code"] == "store_unavailable");
    const auto poll = client.Get(done.c_str());
    REQUIRE(poll);
    CHECK(poll->status == 503);
    CHECK(server.server->metrics_text().find("rollgap_store_up 0") != std::string::npos);

    REQUIRE(postgres.start());
    resume_jobs(server, client, request);
    CHECK(body_json(client.Get(done.c_str()))["state"] == "succeeded");
    // The refused submission left nothing behind.
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].size() == 2);
}
