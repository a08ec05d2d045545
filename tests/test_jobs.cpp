// The HTTP service's job store (service/jobs.h): states, bounded size, expiry after the
// retention, cancel semantics, and ids that cannot be guessed.

#include "service/jobs.h"

#include <doctest/doctest.h>

#include <chrono>
#include <regex>
#include <set>

using namespace rollgap;
using namespace rollgap::service;
using nlohmann::json;

namespace {

struct FakeClock {
    std::chrono::steady_clock::time_point now = std::chrono::steady_clock::now();
    JobStore::SteadyClock function() {
        return [this] { return now; };
    }
};

Outcome ok_outcome() {
    return Outcome{200, json{{"analysis", "roll_gap"}, {"result", {{"status", "ok"}}}},
                   std::nullopt};
}

const auto far_deadline = std::chrono::steady_clock::now() + std::chrono::hours(1);

}  // namespace

TEST_CASE("jobs: queued, running, succeeded, with the result in the document") {
    JobStore store(4, std::chrono::minutes(10), "replica-a");
    const auto job = store.create("roll_gap", json{{"analysis", "roll_gap"}}, far_deadline);
    REQUIRE(job);
    json document = *store.document(job->id);
    CHECK(document["state"] == "queued");
    CHECK(document["instance"] == "replica-a");
    CHECK(document["progress"] == 0.0);
    CHECK_FALSE(document.contains("result"));

    REQUIRE(store.start(job));
    CHECK((*store.document(job->id))["state"] == "running");
    job->progress = 0.25;
    CHECK((*store.document(job->id))["progress"] == 0.25);

    store.finish(job, ok_outcome());
    document = *store.document(job->id);
    CHECK(document["state"] == "succeeded");
    CHECK(document["progress"] == 1.0);
    CHECK(document["result"]["result"]["status"] == "ok");
    CHECK(document.contains("started_at"));
    CHECK(document.contains("finished_at"));
    CHECK(document.contains("expires_at"));
    CHECK(job->request.is_null());  // released once finished
}

TEST_CASE("jobs: a failed job carries its problem") {
    JobStore store(4, std::chrono::minutes(10), "r");
    const auto job = store.create("roll_gap", json::object(), far_deadline);
    REQUIRE(store.start(job));
    store.finish(job,
                 problem_outcome(api::make_problem(api::ProblemCode::invalid_scenario, "bad")));
    const json document = *store.document(job->id);
    CHECK(document["state"] == "failed");
    CHECK(document["problem"]["status"] == 422);
    CHECK_FALSE(document.contains("result"));
}

TEST_CASE(
    "jobs: the store is bounded; finished jobs expire after the retention and free their slot") {
    FakeClock clock;
    JobStore store(2, std::chrono::seconds(60), "r", clock.function());
    const auto a = store.create("roll_gap", json::object(), far_deadline);
    const auto b = store.create("roll_gap", json::object(), far_deadline);
    REQUIRE(a);
    REQUIRE(b);
    CHECK_FALSE(store.create("roll_gap", json::object(), far_deadline));  // full

    REQUIRE(store.start(a));
    store.finish(a, ok_outcome());
    clock.now += std::chrono::seconds(59);
    CHECK(store.document(a->id));
    CHECK_FALSE(store.create("roll_gap", json::object(), far_deadline));  // a is still kept
    clock.now += std::chrono::seconds(2);
    CHECK_FALSE(store.document(a->id));                             // expired
    CHECK(store.create("roll_gap", json::object(), far_deadline));  // its slot is free
    CHECK(store.counts().total() == 2);
}

TEST_CASE("jobs: cancel a queued job, a running job, delete a finished one") {
    JobStore store(8, std::chrono::minutes(10), "r");

    const auto queued = store.create("roll_gap", json::object(), far_deadline);
    json document;
    CHECK(store.cancel(queued->id, &document) == CancelResult::cancelled);
    CHECK(document["state"] == "cancelled");
    CHECK_FALSE(store.start(queued));  // it must not run any more

    const auto running = store.create("roll_gap", json::object(), far_deadline);
    REQUIRE(store.start(running));
    CHECK(store.cancel(running->id, &document) == CancelResult::cancel_requested);
    CHECK(document["state"] == "running");
    CHECK(document["cancel_requested"] == true);
    CHECK(running->cancel_requested);
    store.finish(running, ok_outcome());  // whatever it returns, it was cancelled
    CHECK((*store.document(running->id))["state"] == "cancelled");

    const auto finished = store.create("roll_gap", json::object(), far_deadline);
    REQUIRE(store.start(finished));
    store.finish(finished, ok_outcome());
    CHECK(store.cancel(finished->id) == CancelResult::deleted);
    CHECK_FALSE(store.document(finished->id));
    CHECK(store.cancel("0123456789abcdef0123456789abcdef") == CancelResult::not_found);
}

TEST_CASE("jobs: cancel_all stops queued and running jobs") {
    JobStore store(8, std::chrono::minutes(10), "r");
    const auto queued = store.create("roll_gap", json::object(), far_deadline);
    const auto running = store.create("roll_gap", json::object(), far_deadline);
    REQUIRE(store.start(running));
    store.cancel_all();
    CHECK((*store.document(queued->id))["state"] == "cancelled");
    CHECK(running->cancel_requested);
    CHECK(store.counts().active() == 1);  // the running one until its computation returns
}

TEST_CASE("jobs: ids are 32 random hex digits, timestamps RFC 3339 UTC") {
    std::set<std::string> ids;
    const std::regex hex("^[0-9a-f]{32}$");
    for (int i = 0; i < 200; ++i) {
        const std::string id = random_job_id();
        CHECK(std::regex_match(id, hex));
        ids.insert(id);
    }
    CHECK(ids.size() == 200);
    const auto epoch_plus =
        std::chrono::system_clock::time_point(std::chrono::milliseconds(86'400'000LL + 1234));
    CHECK(rfc3339(epoch_plus) == "1970-01-02T00:00:01.234Z");
}

TEST_CASE("job store: a full store gives the slot of the oldest cancelled job to a new one") {
    service::JobStore store(2, std::chrono::minutes(10), "test");
    const auto running =
        store.create("roll_gap", nlohmann::json::object(), std::chrono::steady_clock::now());
    REQUIRE(running);
    REQUIRE(store.start(running));
    const auto queued =
        store.create("roll_gap", nlohmann::json::object(), std::chrono::steady_clock::now());
    REQUIRE(queued);
    CHECK_FALSE(
        store.create("roll_gap", nlohmann::json::object(), std::chrono::steady_clock::now()));
    CHECK(store.cancel(queued->id) == service::CancelResult::cancelled);
    const auto next =
        store.create("roll_gap", nlohmann::json::object(), std::chrono::steady_clock::now());
    REQUIRE(next);
    CHECK_FALSE(store.document(queued->id).has_value());  // evicted
    CHECK(store.document(running->id).has_value());       // a running job is never evicted
    CHECK(store.counts().total() == 2);
}
