// The durable job store (service/store/) against real databases: every behavioural test runs
// on both backends, SQLite in a fresh directory and PostgreSQL 15 started by the test itself
// (tests/support/postgres.h). Time is a manual clock so that lease expiry and retention are
// exact, not timing-dependent.

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>
#include <nlohmann/json.hpp>

#include "service/store/job_store.h"
#include "support/postgres.h"
#include "support/approx.h"

namespace {

using namespace rollgap::service::store;
using namespace std::chrono_literals;
using rollgap::test::PostgresServer;

struct ManualClock {
    std::shared_ptr<std::atomic<Millis>> now =
        std::make_shared<std::atomic<Millis>>(1'700'000'000'000);
    Clock clock() const {
        return [n = now] { return n->load(); };
    }
    void advance(std::chrono::milliseconds by) const { *now += by.count(); }
};

std::string temp_dir() {
    char pattern[] = "/tmp/rollgap-store-XXXXXX";
    REQUIRE(::mkdtemp(pattern) != nullptr);
    return pattern;
}

struct SqliteDb {
    static constexpr const char* name = "sqlite";
    std::string dir = temp_dir();
    ~SqliteDb() {
        std::error_code ignored;
        std::filesystem::remove_all(dir, ignored);
    }
    std::string setting() const { return "sqlite:" + dir + "/jobs.db"; }
    PostgresServer* server() const { return nullptr; }
};

PostgresServer& shared_postgres() {
    static PostgresServer server;
    return server;
}

struct PostgresDb {
    static constexpr const char* name = "postgresql";
    std::string dsn;
    PostgresDb() {
        static int databases = 0;
        auto& server = shared_postgres();
        if (!server.running()) server.start();
        REQUIRE_MESSAGE(server.running(), server.error());
        dsn = server.create_database("store_test_" + std::to_string(++databases));
        REQUIRE(!dsn.empty());
    }
    std::string setting() const { return dsn; }
    PostgresServer* server() const { return &shared_postgres(); }
};

template <class Db>
std::shared_ptr<JobStore> open(const Db& db, const ManualClock& clock, StoreLimits limits = {}) {
    auto store = open_store(db.setting(), limits, clock.clock());
    REQUIRE_MESSAGE(store.ok(), status_name(store.status), ": ", store.detail);
    return *store.value;
}

NewJob job_spec(std::string request = R"({"analysis":"stability"})") {
    NewJob spec;
    spec.analysis = "stability";
    spec.request = std::move(request);
    spec.instance = "replica-a";
    spec.deadline_ms = 1'800'000'000'000;
    return spec;
}

std::string create_id(JobStore& store, NewJob spec = job_spec()) {
    auto created = store.create(spec);
    REQUIRE_MESSAGE(created.ok(), status_name(created.status), ": ", created.detail);
    return created.value->job.id;
}

WorkItem claim_one(JobStore& store, const std::string& owner,
                   std::chrono::milliseconds lease = 10s) {
    auto claimed = store.claim(owner, lease);
    REQUIRE_MESSAGE(claimed.ok(), claimed.detail);
    REQUIRE(claimed.value->has_value());
    return **claimed.value;
}

// A chunk's result: the indices of its points, so that assembly can be checked point by point.
std::string points_of(const WorkItem& item) {
    auto points = nlohmann::json::array();
    for (auto i = item.begin; i < item.end; ++i) points.push_back(i);
    return points.dump();
}

std::size_t store_count(JobStore& store, JobState state) {
    auto listed = store.list({state, 1000, std::nullopt, {}});
    REQUIRE(listed.ok());
    return listed.value->jobs.size();
}

}  // namespace

#define STORE_BACKENDS SqliteDb, PostgresDb

TEST_CASE_TEMPLATE(
    "job store: the same key and body return the same job, another body is a conflict", Db,
    STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    NewJob spec = job_spec();
    spec.idempotency_key = "order-4711";
    spec.body_hash = "hash-a";
    auto first = store->create(spec);
    REQUIRE(first.ok());
    CHECK(first.value->created);
    auto again = store->create(spec);
    REQUIRE(again.ok());
    CHECK_FALSE(again.value->created);
    CHECK(again.value->job.id == first.value->job.id);

    spec.body_hash = "hash-b";
    CHECK(store->create(spec).status == StoreStatus::conflict);

    // Without a key every submission is a new job.
    CHECK(create_id(*store) != create_id(*store));
    CHECK(store->list({}).value->jobs.size() == 3);
}

TEST_CASE_TEMPLATE("job store: list is newest first, filtered by state, paged by cursor", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    std::vector<std::string> ids;
    for (int i = 0; i < 7; ++i) {
        ids.push_back(create_id(*store));
        clock.advance(1ms);
    }
    std::vector<std::string> seen;
    std::optional<std::string> cursor;
    std::vector<std::size_t> page_sizes;
    for (int page = 0; page < 10; ++page) {
        auto listed = store->list({std::nullopt, 3, cursor, {}});
        REQUIRE(listed.ok());
        page_sizes.push_back(listed.value->jobs.size());
        for (const auto& job : listed.value->jobs) seen.push_back(job.id);
        cursor = listed.value->next_cursor;
        if (!cursor) break;
    }
    CHECK(page_sizes == std::vector<std::size_t>{3, 3, 1});
    CHECK(seen == std::vector<std::string>(ids.rbegin(), ids.rend()));

    REQUIRE(store->cancel(ids[1]).value == CancelResult::cancelled);
    REQUIRE(store->cancel(ids[4]).value == CancelResult::cancelled);
    auto cancelled = store->list({JobState::cancelled, 10, std::nullopt, {}});
    REQUIRE(cancelled.ok());
    REQUIRE(cancelled.value->jobs.size() == 2);
    CHECK(cancelled.value->jobs[0].id == ids[4]);
    CHECK(cancelled.value->jobs[1].id == ids[1]);
    CHECK_FALSE(cancelled.value->next_cursor);
    CHECK(store->list({JobState::queued, 10, std::nullopt, {}}).value->jobs.size() == 5);

    CHECK(store->list({std::nullopt, 3, std::string("not-a-cursor"), {}}).status ==
          StoreStatus::invalid);
}

TEST_CASE_TEMPLATE("job store: two concurrent claimers never claim the same job", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto first = open(db, clock);
    auto second = open(db, clock);  // another connection, as another process or replica would have
    constexpr int jobs = 40;
    std::set<std::string> created;
    for (int i = 0; i < jobs; ++i) created.insert(create_id(*first));

    std::vector<std::string> claimed_a, claimed_b;
    std::atomic<int> failures{0};
    auto worker = [&](JobStore& store, std::vector<std::string>& claimed, const char* owner) {
        for (int attempts = 0; attempts < 10 * jobs; ++attempts) {
            auto item = store.claim(owner, 30s);
            if (!item.ok()) {
                ++failures;
                continue;
            }
            if (!*item.value) {
                if (store_count(store, JobState::queued) == 0) break;
                continue;
            }
            claimed.push_back((*item.value)->lease.job_id);
            if (store.complete((*item.value)->lease, FinalState::succeeded, R"({"ok":true})")
                    .status != StoreStatus::ok) {
                ++failures;
            }
        }
    };
    std::thread a(worker, std::ref(*first), std::ref(claimed_a), "a");
    std::thread b(worker, std::ref(*second), std::ref(claimed_b), "b");
    a.join();
    b.join();
    CHECK(failures == 0);
    std::multiset<std::string> all(claimed_a.begin(), claimed_a.end());
    all.insert(claimed_b.begin(), claimed_b.end());
    CHECK(all.size() == jobs);
    CHECK(std::set<std::string>(all.begin(), all.end()) == created);
    CHECK(store_count(*first, JobState::succeeded) == jobs);
    MESSAGE(std::string(Db::name), ": claims by a ", claimed_a.size(), ", by b ", claimed_b.size());
}

TEST_CASE_TEMPLATE(
    "job store: an expired lease hands the work over, the old holder can no longer write", Db,
    STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    const std::string id = create_id(*store);
    const WorkItem dead = claim_one(*store, "replica-a", 1000ms);
    CHECK(store->get(id).value->state == JobState::running);

    clock.advance(500ms);
    CHECK_FALSE(store->claim("replica-b", 1000ms).value->has_value());  // still leased

    clock.advance(600ms);  // replica-a stopped renewing: its lease ran out
    const WorkItem taken = claim_one(*store, "replica-b", 1000ms);
    CHECK(taken.lease.job_id == id);
    CHECK(taken.lease.token != dead.lease.token);

    CHECK(store->renew(dead.lease, 1000ms).status == StoreStatus::conflict);
    CHECK(store->progress(dead.lease, 0.5) == StoreStatus::conflict);
    CHECK(store->complete(dead.lease, FinalState::succeeded, R"({"from":"a"})").status ==
          StoreStatus::conflict);
    CHECK(store->complete(taken.lease, FinalState::succeeded, R"({"from":"b"})").value ==
          JobState::succeeded);
    const auto job = store->get(id);
    CHECK(job.value->state == JobState::succeeded);
    CHECK(job.value->result == std::string(R"({"from":"b"})"));

    // expire_leases queues expired work explicitly (e.g. on a timer), counting it.
    const std::string second = create_id(*store);
    const WorkItem lost = claim_one(*store, "replica-a", 1000ms);
    CHECK(lost.lease.job_id == second);
    CHECK(store->expire_leases().value == 0);
    clock.advance(1001ms);
    CHECK(store->expire_leases().value == 1);
    CHECK(claim_one(*store, "replica-b").lease.job_id == second);
}

TEST_CASE_TEMPLATE(
    "job store: renewing and progress keep a lease, release gives it to another replica", Db,
    STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    const std::string id = create_id(*store);
    const WorkItem item = claim_one(*store, "replica-a", 1000ms);
    for (int i = 0; i < 5; ++i) {
        clock.advance(800ms);
        const auto renewed = store->renew(item.lease, 1000ms);
        REQUIRE(renewed.ok());
        CHECK_FALSE(renewed.value->cancel_requested);
        CHECK_FALSE(store->claim("replica-b", 1000ms).value->has_value());
    }
    CHECK(store->progress(item.lease, 0.25) == StoreStatus::ok);
    CHECK(store->get(id).value->progress == rollgap::test::approx(0.25));

    CHECK(store->release(item.lease) == StoreStatus::ok);  // draining replica
    CHECK(store->get(id).value->state == JobState::running);
    const WorkItem next = claim_one(*store, "replica-b");
    CHECK(next.lease.job_id == id);
    CHECK(store->complete(item.lease, FinalState::succeeded, "{}").status == StoreStatus::conflict);
}

TEST_CASE_TEMPLATE(
    "job store: cancel — queued at once, running through the worker's renew, finished deleted", Db,
    STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    const std::string running = create_id(*store);
    const std::string queued = create_id(*store);
    const WorkItem item = claim_one(*store, "replica-a");
    REQUIRE(item.lease.job_id == running);

    CHECK(store->cancel(queued).value == CancelResult::cancelled);
    CHECK(store->get(queued).value->state == JobState::cancelled);
    CHECK_FALSE(store->claim("replica-b", 1s).value->has_value());  // a cancelled job never runs

    CHECK(store->cancel(running).value == CancelResult::cancel_requested);
    CHECK(store->get(running).value->cancel_requested);
    const auto renewed = store->renew(item.lease, 10s);
    REQUIRE(renewed.ok());
    CHECK(renewed.value->cancel_requested);
    CHECK(store->complete(item.lease, FinalState::cancelled, "").value == JobState::cancelled);

    CHECK(store->cancel(running).value == CancelResult::deleted);
    CHECK(store->get(running).status == StoreStatus::not_found);
    CHECK(store->cancel(running).status == StoreStatus::not_found);

    // A cancel waiting for a worker that died is finished when its lease is expired.
    const std::string orphan = create_id(*store);
    const WorkItem dying = claim_one(*store, "replica-a", 1000ms);
    REQUIRE(dying.lease.job_id == orphan);
    CHECK(store->cancel(orphan).value == CancelResult::cancel_requested);
    clock.advance(2s);
    CHECK(store->expire_leases().value == 1);
    CHECK(store->get(orphan).value->state == JobState::cancelled);
}

TEST_CASE_TEMPLATE(
    "job store: a finished job's callback is queued with its completion, attempted under a lease",
    Db, STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    NewJob spec = job_spec();
    spec.callback_url = "http://127.0.0.1:9/hooks/rollgap";
    const std::string id = create_id(*store, spec);
    const auto callback = [&] {
        auto job = store->get(id);
        REQUIRE(job.ok());
        REQUIRE(job.value->callback.has_value());
        return *job.value->callback;
    };
    CHECK(callback().url == *spec.callback_url);
    CHECK(callback().state == "pending");
    CHECK(callback().attempts == 0);
    CHECK_FALSE(store->claim_delivery("replica-a", 30s).value->has_value());  // not finished

    const WorkItem item = claim_one(*store, "replica-a");
    REQUIRE(store->complete(item.lease, FinalState::succeeded, "{}").ok());
    const auto first = store->claim_delivery("replica-a", 30s);
    REQUIRE(first.ok());
    REQUIRE(first.value->has_value());
    const Delivery a = **first.value;
    CHECK(a.job_id == id);
    CHECK(a.url == *spec.callback_url);
    CHECK(a.job_state == JobState::succeeded);
    CHECK_FALSE(a.body.has_value());
    CHECK(a.attempts == 0);
    // one replica at a time: the lease holds it
    CHECK_FALSE(store->claim_delivery("replica-b", 30s).value->has_value());
    REQUIRE(store->set_delivery_body(a, R"({"event":"job.finished"})") == StoreStatus::ok);
    const Millis now = clock.clock()();
    REQUIRE(store->record_delivery(a, DeliveryOutcome::retry, now + 1000, "HTTP 503") ==
            StoreStatus::ok);
    CHECK(callback().state == "pending");
    CHECK(callback().attempts == 1);
    CHECK(callback().last_error == std::string("HTTP 503"));
    // a retry is due at its time, not before; it carries the first attempt's body and id
    CHECK_FALSE(store->claim_delivery("replica-b", 30s).value->has_value());
    clock.advance(1s);
    const Delivery b = **store->claim_delivery("replica-b", 30s).value;
    CHECK(b.id == a.id);
    CHECK(b.body == std::string(R"({"event":"job.finished"})"));
    CHECK(b.attempts == 1);
    // the first claim's lease is spent: its late answer is refused
    CHECK(store->record_delivery(a, DeliveryOutcome::delivered, now, "") == StoreStatus::conflict);
    // replica-b dies mid-attempt: once its lease runs out, another replica attempts again
    clock.advance(31s);
    const Delivery c = **store->claim_delivery("replica-a", 30s).value;
    CHECK(c.id == a.id);
    CHECK(c.attempts == 1);
    CHECK(store->record_delivery(b, DeliveryOutcome::delivered, now, "") == StoreStatus::conflict);
    REQUIRE(store->record_delivery(c, DeliveryOutcome::delivered, now, "") == StoreStatus::ok);
    CHECK(callback().state == "delivered");
    CHECK(callback().attempts == 2);
    CHECK_FALSE(callback().last_error.has_value());
    clock.advance(3600s);
    CHECK_FALSE(store->claim_delivery("replica-a", 30s).value->has_value());  // delivered once

    // a job without a callback queues none; a cancelled one announces its cancellation; a
    // delivery given up is failed
    const std::string plain = create_id(*store);
    CHECK(store->cancel(plain).value == CancelResult::cancelled);
    CHECK_FALSE(store->get(plain).value->callback.has_value());
    CHECK_FALSE(store->claim_delivery("replica-a", 30s).value->has_value());
    spec.idempotency_key.reset();
    const std::string cancelled = create_id(*store, spec);
    CHECK(store->cancel(cancelled).value == CancelResult::cancelled);
    const Delivery d = **store->claim_delivery("replica-a", 30s).value;
    CHECK(d.job_id == cancelled);
    CHECK(d.job_state == JobState::cancelled);
    REQUIRE(store->record_delivery(d, DeliveryOutcome::failed, now, "connection refused") ==
            StoreStatus::ok);
    auto given_up = store->get(cancelled);
    CHECK(given_up.value->callback->state == "failed");
    CHECK(given_up.value->callback->last_error == std::string("connection refused"));
    CHECK_FALSE(store->claim_delivery("replica-a", 30s).value->has_value());
}

TEST_CASE_TEMPLATE("job store: a failed item fails the job with its problem", Db, STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    const std::string id = create_id(*store);
    const WorkItem item = claim_one(*store, "replica-a");
    CHECK(store->complete(item.lease, FinalState::failed, R"({"status":422})").value ==
          JobState::failed);
    const auto job = store->get(id);
    CHECK(job.value->state == JobState::failed);
    CHECK(job.value->problem == std::string(R"({"status":422})"));
    CHECK_FALSE(job.value->result);
    CHECK(job.value->finished_ms == clock.now->load());
}

TEST_CASE_TEMPLATE("job store: chunks claimed by two workers assemble every point exactly once", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto first = open(db, clock);
    auto second = open(db, clock);
    NewJob spec = job_spec();
    spec.analysis = "sweep";
    spec.points = 103;
    spec.chunk_size = 10;
    const std::string id = create_id(*first, spec);
    auto created = first->get(id);
    CHECK(created.value->chunks == 11);
    CHECK(created.value->points == 103);

    // Chunk 0 is computed twice: its first worker's lease runs out and another takes it;
    // only the holder's result counts.
    const WorkItem slow = claim_one(*first, "replica-a", 1000ms);
    CHECK(slow.begin == 0);
    CHECK(slow.end == 10);
    clock.advance(1001ms);
    const WorkItem retaken = claim_one(*second, "replica-b", 60s);
    CHECK(retaken.lease.chunk == 0);
    CHECK(second->complete(retaken.lease, FinalState::succeeded, points_of(retaken)).value ==
          JobState::running);
    CHECK(first->complete(slow.lease, FinalState::succeeded, points_of(slow)).status ==
          StoreStatus::conflict);

    // A result that is not exactly the chunk's points is refused.
    const WorkItem odd = claim_one(*first, "replica-a", 60s);
    CHECK(first->complete(odd.lease, FinalState::succeeded, "[1,2]").status ==
          StoreStatus::invalid);
    CHECK(first->complete(odd.lease, FinalState::succeeded, points_of(odd)).value ==
          JobState::running);

    // Partial results while it runs: the finished chunks, in point order.
    const auto running = first->get(id);
    CHECK(running.value->state == JobState::running);
    CHECK(running.value->points_done == 20);
    CHECK(running.value->chunks_done == 2);
    CHECK(running.value->progress == rollgap::test::approx(20.0 / 103.0));
    const auto partial = first->finished_chunks(id);
    REQUIRE(partial.ok());
    REQUIRE(partial.value->size() == 2);
    CHECK((*partial.value)[0].begin == 0);
    CHECK((*partial.value)[1].begin == 10);

    std::atomic<int> failures{0};
    std::vector<std::int64_t> chunks_a, chunks_b;
    auto worker = [&](JobStore& store, std::vector<std::int64_t>& chunks, const char* owner) {
        for (int attempts = 0; attempts < 200; ++attempts) {
            auto item = store.claim(owner, 60s);
            if (!item.ok()) {
                ++failures;
                continue;
            }
            if (!*item.value) {
                if (store.get(id).value->state != JobState::running) break;
                std::this_thread::yield();
                continue;
            }
            chunks.push_back((*item.value)->lease.chunk);
            if (!store
                     .complete((*item.value)->lease, FinalState::succeeded, points_of(**item.value))
                     .ok())
                ++failures;
        }
    };
    std::thread a(worker, std::ref(*first), std::ref(chunks_a), "a");
    std::thread b(worker, std::ref(*second), std::ref(chunks_b), "b");
    a.join();
    b.join();
    CHECK(failures == 0);
    CHECK(chunks_a.size() + chunks_b.size() == 9);

    const auto done = first->get(id);
    REQUIRE(done.value->state == JobState::succeeded);
    CHECK(done.value->progress == 1.0);
    const auto points = nlohmann::json::parse(done.value->result.value_or("null"));
    REQUIRE(points.is_array());
    REQUIRE(points.size() == 103);
    for (std::size_t i = 0; i < points.size(); ++i) CHECK(points[i] == i);
}

TEST_CASE_TEMPLATE("job store: cancelling a sweep stops handing out its chunks", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    NewJob spec = job_spec();
    spec.points = 30;
    spec.chunk_size = 10;
    const std::string id = create_id(*store, spec);
    const WorkItem item = claim_one(*store, "replica-a");
    CHECK(store->cancel(id).value == CancelResult::cancel_requested);
    CHECK_FALSE(store->claim("replica-b", 1s).value->has_value());
    CHECK(store->complete(item.lease, FinalState::cancelled, "").value == JobState::cancelled);
    CHECK_FALSE(store->claim("replica-b", 1s).value->has_value());
}

TEST_CASE_TEMPLATE("job store: retention purges finished jobs, the size bound refuses more", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    StoreLimits limits;
    limits.max_jobs = 3;
    limits.retention = 60s;
    auto store = open(db, clock, limits);
    const std::string a = create_id(*store);
    create_id(*store);
    create_id(*store);
    CHECK(store->create(job_spec()).status == StoreStatus::full);  // three queued

    const WorkItem item = claim_one(*store, "replica-a");
    REQUIRE(item.lease.job_id == a);
    REQUIRE(store->complete(item.lease, FinalState::succeeded, "{}").ok());
    // a finished job holds no slot of max_jobs (finished jobs are bounded apart)
    const std::string d = create_id(*store);
    CHECK(store->create(job_spec()).status == StoreStatus::full);
    clock.advance(59s);
    CHECK(store->get(a).ok());  // still retained
    clock.advance(2s);
    CHECK(store->purge().value == 1);  // the finished job expired
    CHECK(store->get(a).status == StoreStatus::not_found);
    CHECK(store->get(d).ok());
    CHECK(store->purge().value == 0);
}

TEST_CASE_TEMPLATE("job store: a job's own retention, and finished jobs bounded oldest first", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    StoreLimits limits;
    limits.retention = 60s;
    limits.max_finished_jobs = 2;
    auto store = open(db, clock, limits);
    NewJob brief = job_spec();
    brief.retention_ms = 10'000;
    NewJob long_kept = job_spec();
    long_kept.retention_ms = 3'600'000;
    const std::string a = create_id(*store, brief);
    const std::string b = create_id(*store, long_kept);
    const std::string c = create_id(*store);
    CHECK(store->get(a).value->retention_ms == 10'000);
    CHECK_FALSE(store->get(c).value->retention_ms.has_value());
    for (int i = 0; i < 3; ++i) {
        const WorkItem item = claim_one(*store, "replica-a");
        REQUIRE(store->complete(item.lease, FinalState::succeeded, "{}").ok());
        clock.advance(1s);
    }
    clock.advance(10s);  // a: 13 s after it finished, past its 10 s
    CHECK(store->purge().value == 1);
    CHECK(store->get(a).status == StoreStatus::not_found);
    clock.advance(60s);  // c: past the store's 60 s; b keeps its hour
    CHECK(store->purge().value == 1);
    CHECK(store->get(c).status == StoreStatus::not_found);
    CHECK(store->get(b).ok());
    // Three more finish: beyond max_finished_jobs (2) the oldest finished go first, b with them
    // whatever its retention.
    std::vector<std::string> later;
    for (int i = 0; i < 3; ++i) {
        later.push_back(create_id(*store));
        const WorkItem item = claim_one(*store, "replica-a");
        REQUIRE(store->complete(item.lease, FinalState::succeeded, "{}").ok());
        clock.advance(1s);
    }
    create_id(*store);  // the bound is kept when a job is created
    CHECK(store->get(b).status == StoreStatus::not_found);
    CHECK(store->get(later[0]).status == StoreStatus::not_found);
    CHECK(store->get(later[1]).ok());
    CHECK(store->get(later[2]).ok());
}

TEST_CASE_TEMPLATE("job store: labels are kept and filter the list, every one of them", Db,
                   STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    const auto labelled = [&](std::vector<std::pair<std::string, std::string>> labels) {
        NewJob spec = job_spec();
        spec.labels = std::move(labels);
        return create_id(*store, spec);
    };
    const std::string c1 = labelled({{"coil", "C-1"}, {"line", "TCM2"}});
    const std::string c2 = labelled({{"coil", "C-2"}, {"line", "TCM2"}});
    const std::string other = labelled({{"coil", "C-1"}, {"line", "TCM1"}});
    create_id(*store);
    CHECK(store->get(c1).value->labels ==
          std::vector<std::pair<std::string, std::string>>{{"coil", "C-1"}, {"line", "TCM2"}});
    const auto ids = [&](std::vector<std::pair<std::string, std::string>> labels) {
        ListQuery query;
        query.labels = std::move(labels);
        const auto page = store->list(query);
        REQUIRE(page.ok());
        std::vector<std::string> found;
        for (const JobRecord& job : page.value->jobs) found.push_back(job.id);
        return found;
    };
    CHECK(ids({{"line", "TCM2"}}) == std::vector<std::string>{c2, c1});  // newest first
    CHECK(ids({{"coil", "C-1"}}) == std::vector<std::string>{other, c1});
    CHECK(ids({{"coil", "C-1"}, {"line", "TCM2"}}) == std::vector<std::string>{c1});
    CHECK(ids({{"coil", "C-9"}}).empty());
    CHECK(ids({}).size() == 4);
    // a deleted job's labels go with it
    const WorkItem item = claim_one(*store, "replica-a");
    REQUIRE(store->complete(item.lease, FinalState::succeeded, "{}").ok());
    REQUIRE(store->cancel(c1).ok());
    CHECK(ids({{"coil", "C-1"}}) == std::vector<std::string>{other});
}

TEST_CASE_TEMPLATE(
    "job store: stored scenarios are versioned, If-Match conflicts, default is reserved", Db,
    STORE_BACKENDS) {
    Db db;
    ManualClock clock;
    auto store = open(db, clock);
    const auto created = store->put_scenario("mill-3", R"({"stand":1})", std::nullopt);
    REQUIRE(created.ok());
    CHECK(created.value->version == 1);
    // A blind overwrite, or one from a stale version, is a conflict: two editors cannot
    // overwrite each other.
    CHECK(store->put_scenario("mill-3", R"({"stand":2})", std::nullopt).status ==
          StoreStatus::conflict);
    const auto updated = store->put_scenario("mill-3", R"({"stand":2})", 1);
    REQUIRE(updated.ok());
    CHECK(updated.value->version == 2);
    CHECK(store->put_scenario("mill-3", R"({"stand":3})", 1).status == StoreStatus::conflict);
    CHECK(store->put_scenario("mill-9", R"({})", 1).status == StoreStatus::conflict);
    const auto got = store->get_scenario("mill-3");
    CHECK(got.value->body == R"({"stand":2})");
    CHECK(got.value->version == 2);

    CHECK(store->put_scenario("another", "{}", std::nullopt).ok());
    const auto names = store->list_scenarios();
    REQUIRE(names.value->size() == 2);
    CHECK((*names.value)[0].name == "another");
    CHECK((*names.value)[1].name == "mill-3");
    CHECK((*names.value)[1].version == 2);

    CHECK(store->delete_scenario("mill-3", 1) == StoreStatus::conflict);
    CHECK(store->delete_scenario("mill-3", 2) == StoreStatus::ok);
    CHECK(store->get_scenario("mill-3").status == StoreStatus::not_found);
    CHECK(store->delete_scenario("mill-3", std::nullopt) == StoreStatus::not_found);

    CHECK(store->put_scenario("default", "{}", std::nullopt).status == StoreStatus::invalid);
    CHECK(store->get_scenario("default").status == StoreStatus::invalid);
    CHECK(store->delete_scenario("default", std::nullopt) == StoreStatus::invalid);
    CHECK(store->put_scenario("../etc", "{}", std::nullopt).status == StoreStatus::invalid);
}

TEST_CASE(
    "job store (postgresql): stopped database → unavailable, nothing half-written, then back") {
    PostgresDb db;
    ManualClock clock;
    auto store = open(db, clock);
    const std::string before = create_id(*store);
    const WorkItem item = claim_one(*store, "replica-a");
    REQUIRE(db.server()->stop());

    CHECK(store->create(job_spec()).status == StoreStatus::unavailable);
    CHECK(store->get(before).status == StoreStatus::unavailable);
    CHECK(store->complete(item.lease, FinalState::succeeded, "{}").status ==
          StoreStatus::unavailable);
    CHECK(store->put_scenario("mill-1", "{}", std::nullopt).status == StoreStatus::unavailable);
    CHECK(open_store(db.setting(), {}, clock.clock()).status == StoreStatus::unavailable);

    REQUIRE(db.server()->start());
    const auto listed = store->list({});
    REQUIRE(listed.ok());
    REQUIRE(listed.value->jobs.size() == 1);  // the refused create left nothing behind
    CHECK(listed.value->jobs[0].state == JobState::running);
    CHECK(store->get_scenario("mill-1").status == StoreStatus::not_found);
    CHECK(store->complete(item.lease, FinalState::succeeded, "{}").value == JobState::succeeded);
    CHECK(store->create(job_spec()).ok());
}

TEST_CASE("job store (sqlite): jobs survive reopening the file, a queued job then runs") {
    SqliteDb db;
    ManualClock clock;
    std::string finished, queued;
    {
        auto store = open(db, clock);
        finished = create_id(*store);
        queued = create_id(*store);
        const WorkItem item = claim_one(*store, "replica-a");
        REQUIRE(store->complete(item.lease, FinalState::succeeded, R"({"x_m":1})").ok());
        REQUIRE(store->put_scenario("mill-1", "{}", std::nullopt).ok());
    }
    auto store = open(db, clock);
    CHECK(store->get(finished).value->result == std::string(R"({"x_m":1})"));
    CHECK(store->get(queued).value->state == JobState::queued);
    CHECK(claim_one(*store, "replica-a").lease.job_id == queued);
    CHECK(store->get_scenario("mill-1").value->version == 1);
}

TEST_CASE("job store: the setting chooses the backend, a DSN may come from a file") {
    CHECK(open_store("mysql://x").status == StoreStatus::invalid);
    CHECK(open_store("sqlite:").status == StoreStatus::invalid);
    CHECK(open_store("sqlite:/dev/null/jobs.db").status ==
          StoreStatus::unavailable);  // not a directory
    CHECK(open_store("postgresql-file:/nonexistent-file").status == StoreStatus::invalid);

    PostgresDb db;
    SqliteDb dir;
    const std::string file = dir.dir + "/dsn";
    std::ofstream(file) << db.setting() << "\n";
    ManualClock clock;
    auto store = open_store("postgresql-file:" + file, {}, clock.clock());
    REQUIRE(store.ok());
    CHECK((*store.value)->create(job_spec()).ok());
    // Migrating an already migrated database changes nothing.
    auto again = open_store(db.setting(), {}, clock.clock());
    REQUIRE(again.ok());
    CHECK((*again.value)->list({}).value->jobs.size() == 1);
}
