// The HTTP service's compute pool (service/worker_pool.h): bounded lanes that refuse at once
// when full, interactive work first, a cap on concurrently running batch work, and a shutdown
// that finishes what was queued.

#include "service/worker_pool.h"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "support/http_test.h"

using namespace rollgap::service;
using rollgap::test::eventually;

namespace {

// Tasks that block until the latch opens.
class Latch {
public:
    WorkerPool::Task blocking_task(std::atomic<int>& done) {
        return [this, &done] {
            std::unique_lock lock(mutex_);
            opened_.wait_for(lock, std::chrono::seconds(10), [this] { return open_; });
            ++done;
        };
    }
    void open() {
        {
            std::lock_guard lock(mutex_);
            open_ = true;
        }
        opened_.notify_all();
    }

private:
    std::mutex mutex_;
    std::condition_variable opened_;
    bool open_ = false;
};

}  // namespace

TEST_CASE("worker pool: runs submitted tasks on its workers") {
    WorkerPool pool(2, 16, 16, 1);
    std::atomic<int> done{0};
    for (int i = 0; i < 10; ++i) CHECK(pool.try_submit(Lane::interactive, [&done] { ++done; }));
    CHECK(eventually([&] { return done == 10; }));
    CHECK(eventually([&] { return pool.idle(); }));
    CHECK(pool.stats().workers == 2);
}

TEST_CASE("worker pool: a full interactive lane refuses at once") {
    WorkerPool pool(1, 1, 4, 1);
    Latch latch;
    std::atomic<int> done{0};
    REQUIRE(pool.try_submit(Lane::interactive, latch.blocking_task(done)));  // runs
    REQUIRE(eventually([&] { return pool.stats().busy == 1; }));
    REQUIRE(pool.try_submit(Lane::interactive, latch.blocking_task(done)));  // waits
    CHECK(pool.stats().interactive_queued == 1);
    const auto before = std::chrono::steady_clock::now();
    CHECK_FALSE(pool.try_submit(Lane::interactive, latch.blocking_task(done)));  // full
    CHECK(std::chrono::steady_clock::now() - before < std::chrono::milliseconds(50));
    latch.open();
    CHECK(eventually([&] { return done == 2; }));
}

TEST_CASE("worker pool: a zero-length queue still starts work on an idle worker") {
    WorkerPool pool(1, 0, 0, 1);
    std::atomic<int> done{0};
    Latch latch;
    CHECK(pool.try_submit(Lane::interactive, latch.blocking_task(done)));
    REQUIRE(eventually([&] { return pool.stats().busy == 1; }));
    CHECK_FALSE(pool.try_submit(Lane::interactive, [] {}));
    latch.open();
    CHECK(eventually([&] { return done == 1; }));
}

TEST_CASE(
    "worker pool: batch work runs at most batch_concurrency at once and never starves interactive work") {
    WorkerPool pool(2, 4, 8, 1);
    Latch latch;
    std::atomic<int> batch_done{0};
    REQUIRE(pool.try_submit(Lane::batch, latch.blocking_task(batch_done)));
    REQUIRE(pool.try_submit(Lane::batch, latch.blocking_task(batch_done)));
    REQUIRE(eventually([&] { return pool.stats().batch_running == 1; }));
    // The second batch task waits although a worker is free: that worker is for interactive work.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    CHECK(pool.stats().batch_running == 1);
    CHECK(pool.stats().batch_queued == 1);
    std::atomic<int> interactive_done{0};
    CHECK(pool.try_submit(Lane::interactive, [&] { ++interactive_done; }));
    CHECK(eventually([&] { return interactive_done == 1; }));
    latch.open();
    CHECK(eventually([&] { return batch_done == 2; }));
}

TEST_CASE("worker pool: an exception in a task does not take the worker down") {
    WorkerPool pool(1, 4, 4, 1);
    CHECK(pool.try_submit(Lane::interactive, [] { throw std::runtime_error("boom"); }));
    std::atomic<int> done{0};
    CHECK(pool.try_submit(Lane::interactive, [&] { ++done; }));
    CHECK(eventually([&] { return done == 1; }));
}

TEST_CASE("worker pool: shutdown runs the queued tasks, then refuses new ones") {
    std::atomic<int> done{0};
    WorkerPool pool(1, 16, 16, 1);
    for (int i = 0; i < 5; ++i)
        REQUIRE(pool.try_submit(Lane::interactive, [&] {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
            ++done;
        }));
    REQUIRE(pool.try_submit(Lane::batch, [&] { ++done; }));
    pool.shutdown();
    CHECK(done == 6);
    CHECK_FALSE(pool.try_submit(Lane::interactive, [] {}));
    pool.shutdown();  // idempotent
}

TEST_CASE("worker pool: a withdrawn task leaves its lane at once and never runs") {
    WorkerPool pool(1, 4, 2, 1);
    Latch latch;
    std::atomic<int> done{0};
    REQUIRE(pool.try_submit(Lane::batch, latch.blocking_task(done)));
    REQUIRE(eventually([&] { return pool.stats().busy == 1; }));
    int first = 0, second = 0;  // keys
    std::atomic<int> ran{0};
    REQUIRE(pool.try_submit(
        Lane::batch, [&ran] { ++ran; }, &first));
    REQUIRE(pool.try_submit(
        Lane::batch, [&ran] { ++ran; }, &second));
    CHECK_FALSE(pool.try_submit(Lane::batch, [&ran] { ++ran; }));  // the lane holds two
    CHECK(pool.withdraw(&first));
    CHECK_FALSE(pool.withdraw(&first));  // no longer queued
    CHECK(pool.stats().batch_queued == 1);
    CHECK(pool.try_submit(Lane::batch, [&ran] { ++ran; }));  // its place is free
    latch.open();
    CHECK(eventually([&] { return pool.idle(); }));
    CHECK(ran == 2);
    CHECK(done == 1);
}

TEST_CASE("worker pool: helpers of running analyses go before new interactive and batch tasks") {
    WorkerPool pool(1, 4, 4, 1);
    CHECK(pool.concurrency() == 1);
    Latch latch;
    std::atomic<int> done{0};
    REQUIRE(pool.try_submit(Lane::interactive, latch.blocking_task(done)));
    REQUIRE(eventually([&] { return pool.stats().busy == 1; }));
    std::mutex mutex;
    std::vector<std::string> order;
    const auto record = [&](std::string name) {
        return [&mutex, &order, name] {
            std::lock_guard lock(mutex);
            order.push_back(name);
        };
    };
    REQUIRE(pool.try_submit(Lane::batch, record("batch")));
    REQUIRE(pool.try_submit(Lane::interactive, record("interactive")));
    pool.post(record("inner"));  // posted last, run first
    CHECK(pool.stats().inner_queued == 1);
    CHECK_FALSE(pool.idle());
    latch.open();
    REQUIRE(eventually([&] { return pool.idle(); }));
    std::lock_guard lock(mutex);
    CHECK(order == std::vector<std::string>{"inner", "interactive", "batch"});
}

TEST_CASE("worker pool: a pool that has stopped drops helpers instead of keeping them") {
    WorkerPool pool(1, 4, 4, 1);
    pool.shutdown();
    pool.post([] { FAIL("a stopped pool ran a helper"); });
    CHECK(pool.stats().inner_queued == 0);
}
