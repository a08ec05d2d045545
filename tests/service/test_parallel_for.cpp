// Parallel loops on the process's one pool (core/parallel_for.h over service::WorkerPool): the
// caller helps, so loops nested inside pool tasks finish however busy the pool is, on no more
// threads than the pool has, with the results of a serial run; an exception reaches the caller.

#include "core/parallel_for.h"

#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "service/worker_pool.h"
#include "support/http_test.h"

using rollgap::core::Control;
using rollgap::core::parallel_for;
using rollgap::service::Lane;
using rollgap::service::WorkerPool;
using rollgap::test::eventually;

namespace {

// Waits (bounded) until `count` parties have arrived; false on timeout.
class Barrier {
public:
    explicit Barrier(int count) : count_(count) {}
    bool arrive_and_wait(std::chrono::seconds timeout = std::chrono::seconds(20)) {
        std::unique_lock lock(mutex_);
        if (++arrived_ >= count_) all_.notify_all();
        return all_.wait_for(lock, timeout, [this] { return arrived_ >= count_; });
    }

private:
    std::mutex mutex_;
    std::condition_variable all_;
    int count_;
    int arrived_ = 0;
};

// Counts finished tasks; waits (bounded) for a number of them.
class Done {
public:
    void one() {
        {
            std::lock_guard lock(mutex_);
            ++count_;
        }
        changed_.notify_all();
    }
    bool wait_for(int count) {
        std::unique_lock lock(mutex_);
        return changed_.wait_for(lock, std::chrono::seconds(60), [&] { return count_ >= count; });
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    int count_ = 0;
};

// The threads that ran some work.
class Threads {
public:
    void record() {
        std::lock_guard lock(mutex_);
        ids_.insert(std::this_thread::get_id());
    }
    std::size_t count() {
        std::lock_guard lock(mutex_);
        return ids_.size();
    }

private:
    std::mutex mutex_;
    std::set<std::thread::id> ids_;
};

// A value with enough floating-point work that a wrong or duplicated index shows.
double term(int task, int i, int j) {
    double x = 0.0;
    for (int k = 1; k <= 50; ++k) x += std::sin(0.001 * (task + 1) * (i + 1) * (j + k)) / k;
    return x;
}

constexpr int outer_n = 6;
constexpr int inner_n = 16;
using Table = std::vector<std::vector<double>>;

// outer_n × inner_n terms, the inner loops nested in the outer one.
Table nested_table(int task, const Control& control, Threads* threads) {
    Table table(outer_n, std::vector<double>(inner_n, 0.0));
    parallel_for(outer_n, control, [&](int i) {
        parallel_for(inner_n, control, [&](int j) {
            if (threads != nullptr) threads->record();
            table[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = term(task, i, j);
        });
    });
    return table;
}

// `tasks` outer tasks submitted to a pool of `workers`, each computing a nested table; every
// task first waits until `blocked_together` tasks run at once (all workers in outer loops).
void nested_on_pool(std::size_t workers, int tasks, int blocked_together) {
    CAPTURE(workers);
    CAPTURE(tasks);
    WorkerPool pool(workers, 64, 64, 1);
    Control control;
    control.executor = &pool;
    Threads threads;
    Barrier all_running(blocked_together);
    Done done;
    std::vector<Table> tables(static_cast<std::size_t>(tasks));
    std::atomic<int> barrier_timeouts{0};
    for (int t = 0; t < tasks; ++t) {
        REQUIRE(pool.try_submit(Lane::interactive, [&, t] {
            if (t < blocked_together && !all_running.arrive_and_wait()) ++barrier_timeouts;
            tables[static_cast<std::size_t>(t)] = nested_table(t, control, &threads);
            done.one();
        }));
    }
    REQUIRE(done.wait_for(tasks));
    CHECK(barrier_timeouts.load() == 0);
    for (int t = 0; t < tasks; ++t) {
        CAPTURE(t);
        CHECK(tables[static_cast<std::size_t>(t)] == nested_table(t, Control{}, nullptr));
    }
    // Every loop ran on pool threads only: the callers are workers and so are the helpers.
    CHECK(threads.count() <= workers);
    CHECK(threads.count() >= 1);
    CHECK(eventually([&] { return pool.idle(); }));
}

}  // namespace

TEST_CASE("parallel_for: without an executor the caller runs every index once, in order") {
    std::vector<int> order;
    parallel_for(5, Control{}, [&](int i) { order.push_back(i); });
    CHECK(order == std::vector<int>{0, 1, 2, 3, 4});
    parallel_for(0, Control{}, [&](int) { FAIL("no index"); });
}

TEST_CASE("parallel_for: the pool's workers really help the caller") {
    // Two indices that each wait for the other to start finish only if two threads run them:
    // the caller and a worker.
    WorkerPool pool(2, 0, 0, 1);
    Control control;
    control.executor = &pool;
    Barrier both(2);
    std::atomic<int> met{0};
    parallel_for(2, control, [&](int) { met += both.arrive_and_wait() ? 1 : 0; });
    CHECK(met.load() == 2);
}

TEST_CASE(
    "parallel_for: nested loops in pool tasks finish, on at most the pool's threads, "
    "with the serial results") {
    SUBCASE("one worker") { nested_on_pool(1, 3, 1); }
    SUBCASE("two workers") { nested_on_pool(2, 4, 1); }
    // Saturated: every worker is held in an outer loop before any inner loop starts, so every
    // helper the loops post waits in the queue; the callers must do the work themselves.
    SUBCASE("two workers, all in outer loops at once") { nested_on_pool(2, 2, 2); }
    SUBCASE("three workers, all in outer loops at once") { nested_on_pool(3, 5, 3); }
}

TEST_CASE("parallel_for: a helper that starts after the loop returned does nothing") {
    WorkerPool pool(2, 4, 4, 1);
    Control control;
    control.executor = &pool;
    Barrier release(3);
    Barrier started(3);
    // Both workers are busy: the loop's helper waits in the queue and the caller runs all.
    for (int t = 0; t < 2; ++t) {
        REQUIRE(pool.try_submit(Lane::interactive, [&] {
            started.arrive_and_wait();
            release.arrive_and_wait();
        }));
    }
    REQUIRE(started.arrive_and_wait());
    std::atomic<int> calls{0};
    {
        std::vector<int> out(50, 0);  // gone when the helper runs
        parallel_for(50, control, [&](int i) {
            out[static_cast<std::size_t>(i)] = i;
            ++calls;
        });
        CHECK(out[49] == 49);
    }
    CHECK(pool.stats().inner_queued == 1);
    REQUIRE(release.arrive_and_wait());
    CHECK(eventually([&] { return pool.idle(); }));
    CHECK(calls.load() == 50);
}

TEST_CASE("parallel_for: the first exception of the body reaches the caller") {
    const auto throwing = [](const Control& control, std::atomic<int>& calls) {
        parallel_for(200, control, [&](int i) {
            ++calls;
            if (i == 7) throw std::runtime_error("index 7");
        });
    };
    SUBCASE("serial") {
        std::atomic<int> calls{0};
        CHECK_THROWS_WITH_AS(throwing(Control{}, calls), "index 7", std::runtime_error);
        CHECK(calls.load() == 8);  // nothing after the throwing index
    }
    SUBCASE("on a pool, also from inside a pool task") {
        WorkerPool pool(2, 4, 4, 1);
        Control control;
        control.executor = &pool;
        std::atomic<int> calls{0};
        CHECK_THROWS_WITH_AS(throwing(control, calls), "index 7", std::runtime_error);

        std::atomic<bool> caught{false};
        Done done;
        REQUIRE(pool.try_submit(Lane::interactive, [&] {
            std::atomic<int> inner_calls{0};
            try {
                throwing(control, inner_calls);
            } catch (const std::runtime_error& error) {
                caught = std::string(error.what()) == "index 7";
            }
            done.one();
        }));
        REQUIRE(done.wait_for(1));
        CHECK(caught.load());
        // The pool is unharmed.
        CHECK(nested_table(1, control, nullptr) == nested_table(1, Control{}, nullptr));
    }
}

TEST_CASE("parallel_for: the budget caps the helpers, the pool caps the budget") {
    WorkerPool pool(2, 0, 0, 1);
    Control control;
    control.executor = &pool;
    CHECK(control.thread_budget() == 2);
    control.threads = 8;
    CHECK(control.thread_budget() == 2);
    control.threads = 1;
    CHECK(control.thread_budget() == 1);
    // A budget of one posts no helper: the caller's thread runs everything.
    Threads threads;
    parallel_for(40, control, [&](int) { threads.record(); });
    CHECK(threads.count() == 1);
    CHECK(pool.stats().inner_queued == 0);
    CHECK(Control{}.thread_budget() == 1);
}
