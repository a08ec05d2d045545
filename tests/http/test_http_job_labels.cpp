// Jobs for an MES, on a real server and its SQLite store: a job carries the client's labels
// (echoed, and GET /v1/jobs?label=name:value finds it, every label given at once) and its own
// retention (kept past the server's default, up to the server's maximum); what is wrong in
// either is one 422 naming each member.

#include <doctest/doctest.h>

#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace job_labels_test {

bool has_error_at(const json& problem, const std::string& pointer) {
    for (const json& e : problem["errors"])
        if (e["pointer"] == pointer) return true;
    return false;
}

std::vector<std::string> listed(httplib::Client& client, const std::string& query) {
    const json page = body_json(client.Get(("/v1/jobs?" + query).c_str()));
    std::vector<std::string> ids;
    for (const json& job : page["jobs"]) ids.push_back(job["id"]);
    return ids;
}

}  // namespace job_labels_test

namespace jlt = job_labels_test;

TEST_CASE("job labels: echoed, and the list filtered by every label given") {
    TestServer server;
    auto client = server.client();
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    const auto submit = [&](const json& labels) {
        json body = request;
        body["labels"] = labels;
        const auto created = post_json(client, "/v1/jobs", body);
        REQUIRE(created);
        CAPTURE(created->body);
        REQUIRE(created->status == 202);
        return json::parse(created->body);
    };
    const json c1 = submit({{"coil", "C-4711"}, {"line", "TCM2"}});
    const json c2 = submit({{"coil", "C-4712"}, {"line", "TCM2"}});
    const json c3 = submit({{"coil", "C-4711"}, {"line", "TCM1"}, {"order", "A:17/3"}});
    submit(json::object());
    CHECK(c1["labels"] == json{{"coil", "C-4711"}, {"line", "TCM2"}});
    CHECK(poll_until_finished(client, "/v1/jobs/" + c1["id"].get<std::string>())["labels"] ==
          c1["labels"]);
    using ids = std::vector<std::string>;
    CHECK(jlt::listed(client, "label=line:TCM2") == ids{c2["id"], c1["id"]});
    CHECK(jlt::listed(client, "label=coil:C-4711&label=line:TCM2") == ids{c1["id"]});
    // the value may hold ':' and '/' (URL-encoded by the client)
    CHECK(jlt::listed(client, "label=order:A%3A17%2F3") == ids{c3["id"]});
    CHECK(jlt::listed(client, "label=coil:C-0").empty());
    CHECK(jlt::listed(client, "label=coil:C-4711&state=succeeded&limit=100").size() <= 2);
    // more filters than a job can carry labels: refused, not turned into 17 subqueries
    std::string seventeen = "/v1/jobs?label=a:0";  // distinct: httplib folds repeated pairs
    for (const char* value :
         {"1", "2", "3", "4", "5", "6", "7", "8", "9", "10", "11", "12", "13", "14", "15", "16"})
        seventeen += std::string("&label=a:") + value;
    const auto too_many = client.Get(seventeen.c_str());
    REQUIRE(too_many);
    CHECK(too_many->status == 422);
    CHECK(jlt::has_error_at(json::parse(too_many->body), "/query/label"));
    // a filter that is not name:value
    const auto bad = client.Get("/v1/jobs?label=coil");
    REQUIRE(bad);
    CHECK(bad->status == 422);
    CHECK(jlt::has_error_at(json::parse(bad->body), "/query/label"));
}

TEST_CASE("job labels: a job's own retention keeps it past the server's") {
    service::ServerConfig config = test_config();
    config.job_retention = std::chrono::milliseconds(300);
    TestServer server(config);
    auto client = server.client();
    const json request = {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}};
    json kept_request = request;
    kept_request["retention_s"] = 120;
    const std::string kept = submit_job(client, kept_request);
    const std::string brief = submit_job(client, request);
    const json kept_done = poll_until_finished(client, kept);
    REQUIRE(kept_done["state"] == "succeeded");
    CHECK(kept_done["retention_s"] == 120);
    REQUIRE(poll_until_finished(client, brief)["state"] == "succeeded");
    // the server's 300 ms: gone; the job's 120 s: still there
    CHECK(eventually([&] { return client.Get(brief.c_str())->status == 404; },
                     std::chrono::milliseconds(10'000)));
    const auto still = client.Get(kept.c_str());
    REQUIRE(still);
    CHECK(still->status == 200);
    CHECK(json::parse(still->body)["expires_at"] != json::parse(still->body)["finished_at"]);
}

TEST_CASE("job labels: bad labels and retention are one 422 naming each, nothing stored") {
    service::ServerConfig config = test_config();
    config.max_job_retention = std::chrono::hours(24);
    TestServer server(config);
    auto client = server.client();
    const json bad = {{"analysis", "roll_gap"},
                      {"labels", {{"-x", "a"}, {"ok", 5}, {"note", "two\nlines"}, {"fine", "y"}}},
                      {"retention_s", 86401}};
    const auto refused = post_json(client, "/v1/jobs", bad);
    REQUIRE(refused);
    CHECK(refused->status == 422);
    const json problem = json::parse(refused->body);
    CAPTURE(problem.dump());
    CHECK(problem["code"] == "invalid_request");
    CHECK(jlt::has_error_at(problem, "/labels/-x"));
    CHECK(jlt::has_error_at(problem, "/labels/ok"));
    CHECK(jlt::has_error_at(problem, "/labels/note"));
    CHECK_FALSE(jlt::has_error_at(problem, "/labels/fine"));
    CHECK(jlt::has_error_at(problem, "/retention_s"));
    for (const json& e : problem["errors"])
        if (e["pointer"] == "/retention_s") CHECK(e["bound"] == "[1, 86400]");
    json many = {{"analysis", "roll_gap"}, {"labels", json::object()}};
    for (const char* name : {"a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l", "m", "n",
                             "o", "p", "q"})  // 17 labels, one above the bound
        many["labels"][name] = "v";
    CHECK(post_json(client, "/v1/jobs", many)->status == 422);
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].empty());
    // a batch carries labels too
    const json batch = {{"options",
                         {{"analysis", "roll_gap"},
                          {"options", {{"distributions", false}}},
                          {"items", {{{"label", "C-1"}}}}}},
                        {"labels", {{"shift", "night"}}}};
    const auto queued = post_json(client, "/v1/batches", batch);
    REQUIRE(queued);
    CAPTURE(queued->body);
    CHECK(queued->status == 202);
    CHECK(json::parse(queued->body)["labels"] == json{{"shift", "night"}});
}
