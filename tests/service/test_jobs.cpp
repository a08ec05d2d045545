// The job document rendered from a store record (service/jobs.h): states, timestamps RFC 3339
// UTC, expiry after the retention, chunked progress fields; the request hash that recognises a
// retried submission.

#include "service/jobs.h"

#include <doctest/doctest.h>

#include <chrono>
#include <set>
#include <string>

using namespace rollgap;
using namespace rollgap::service;
using nlohmann::json;

namespace {

constexpr store::Millis day_ms = 86'400'000;

store::JobRecord record() {
    store::JobRecord job;
    job.id = "0123456789abcdef0123456789abcdef";
    job.analysis = "roll_gap";
    job.instance = "replica-a";
    job.created_ms = day_ms + 1234;
    return job;
}

}  // namespace

TEST_CASE("jobs: timestamps are RFC 3339 UTC with milliseconds") {
    const auto epoch_plus =
        std::chrono::system_clock::time_point(std::chrono::milliseconds(day_ms + 1234));
    CHECK(rfc3339(epoch_plus) == "1970-01-02T00:00:01.234Z");
    CHECK(rfc3339(store::Millis{day_ms + 1234}) == "1970-01-02T00:00:01.234Z");
    CHECK(rfc3339(store::Millis{0}) == "1970-01-01T00:00:00.000Z");
}

TEST_CASE("jobs: a queued job's document, a finished one carries its result and expiry") {
    store::JobRecord job = record();
    json document = job_document(job, std::chrono::minutes(10), JobDetail::full);
    CHECK(document["id"] == job.id);
    CHECK(document["state"] == "queued");
    CHECK(document["instance"] == "replica-a");
    CHECK(document["created_at"] == "1970-01-02T00:00:01.234Z");
    for (const char* absent : {"started_at", "finished_at", "expires_at", "result", "problem",
                               "cancel_requested", "points_total", "worker"}) {
        CAPTURE(absent);
        CHECK_FALSE(document.contains(absent));
    }

    job.state = store::JobState::succeeded;
    job.worker = "replica-b";
    job.started_ms = day_ms + 2000;
    job.finished_ms = day_ms + 3000;
    job.progress = 1.0;
    job.result = R"({"analysis":"roll_gap","result":{"ok":true}})";
    document = job_document(job, std::chrono::minutes(10), JobDetail::full);
    CHECK(document["state"] == "succeeded");
    CHECK(document["worker"] == "replica-b");
    CHECK(document["finished_at"] == "1970-01-02T00:00:03.000Z");
    CHECK(document["expires_at"] == "1970-01-02T00:10:03.000Z");  // finished + retention
    CHECK(document["result"] == json::parse(*job.result));
    // List entries leave the result out.
    CHECK_FALSE(job_document(job, std::chrono::minutes(10), JobDetail::summary).contains("result"));

    CHECK_FALSE(job_expired(job, std::chrono::minutes(10), day_ms + 3000 + 599'999));
    CHECK(job_expired(job, std::chrono::minutes(10), day_ms + 3000 + 600'000));
    job.finished_ms.reset();
    CHECK_FALSE(job_expired(job, std::chrono::milliseconds(0), day_ms * 1000));
}

TEST_CASE("jobs: a chunked job counts its points, a failed job carries its problem") {
    store::JobRecord job = record();
    job.state = store::JobState::running;
    job.points = 200;
    job.points_done = 50;
    job.progress = 0.25;
    job.cancel_requested = true;
    json document = job_document(job, std::chrono::minutes(1), JobDetail::full);
    CHECK(document["points_total"] == 200);
    CHECK(document["points_done"] == 50);
    CHECK(document["progress"] == 0.25);
    CHECK(document["cancel_requested"] == true);

    job.state = store::JobState::failed;
    job.problem = R"({"code":"invalid_scenario","status":422})";
    document = job_document(job, std::chrono::minutes(1), JobDetail::full);
    CHECK(document["problem"]["code"] == "invalid_scenario");
    CHECK_FALSE(document.contains("result"));
}

TEST_CASE("jobs: the body hash is FNV-1a 64 (published test vectors) and tells bodies apart") {
    // Test vectors of the FNV reference (Fowler, Noll, Vo: "FNV-1a 64" of "", "a", "foobar").
    CHECK(body_hash("") == "cbf29ce484222325");
    CHECK(body_hash("a") == "af63dc4c8601ec8c");
    CHECK(body_hash("foobar") == "85944171f73967e8");
    std::set<std::string> hashes;
    for (int i = 0; i < 500; ++i)
        hashes.insert(body_hash(json{{"analysis", "roll_gap"}, {"n", i}}.dump()));
    CHECK(hashes.size() == 500);
}
