// The bounded store executor (store_executor.h).
//
// How a caller can give up a call safely: the store's rules pass bodies that capture the
// caller's stack by reference. The executor thread runs such a body only while it holds the
// call's mutex, and releases it only inside a statement (the blocking part), with the
// statement's text and parameters copied first. A caller that gives up takes the mutex and
// marks the call abandoned; from then on the body is never resumed: the statement that was
// running throws Abort when it returns, so the transaction rolls back and nothing of the
// caller's is touched again.

#include "service/store/store_executor.h"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace rollgap::service::store::detail {
// Named, not anonymous: StoreExecutor::Shared (declared in the header) holds these, and a
// unity build would make that a type with internal linkage inside one with external linkage.
namespace executor_parts {

using SteadyClock = std::chrono::steady_clock;
constexpr std::string_view abandoned_detail = "the caller gave the call up";

// One call, shared by its caller and the executor thread that runs it.
struct Call {
    bool write = false;
    const std::function<void(Session&)>* body = nullptr;    // the caller's: see the top
    const std::function<bool(Session&)>* verify = nullptr;  // nullptr: none
    std::mutex mutex;
    std::condition_variable finished;
    bool abandoned = false;
    bool done = false;
    StoreStatus status = StoreStatus::unavailable;
    std::string detail;
};

// The caller's body sees this session: each statement runs with the call's mutex released.
class GuardedSession final : public Session {
public:
    GuardedSession(Session& inner, Call& call, std::unique_lock<std::mutex>& lock)
        : inner_(inner), call_(call), lock_(lock) {}

    Rows exec(std::string_view sql, const std::vector<Param>& params) override {
        // Both may live in the caller's frame, which is gone once the call is abandoned.
        const std::string text(sql);
        const std::vector<Param> copied = params;
        lock_.unlock();
        Rows rows;
        try {
            rows = inner_.exec(text, copied);
        } catch (...) {
            lock_.lock();
            throw;
        }
        lock_.lock();
        if (call_.abandoned) throw Abort{StoreStatus::unavailable, std::string(abandoned_detail)};
        return rows;
    }

private:
    Session& inner_;
    Call& call_;
    std::unique_lock<std::mutex>& lock_;
};

}  // namespace executor_parts

using executor_parts::abandoned_detail;
using executor_parts::Call;
using executor_parts::GuardedSession;

struct StoreExecutor::Shared {
    std::unique_ptr<Backend> inner;
    ExecutorOptions options;
    std::mutex mutex;
    std::condition_variable work;
    std::condition_variable exited;
    std::deque<std::shared_ptr<Call>> queue;
    // When each thread took its current call; nullopt while it waits for one.
    std::vector<std::optional<std::chrono::steady_clock::time_point>> busy_since;
    std::size_t running = 0;
    bool stopping = false;

    // Every thread is on a call that started more than a deadline ago: the database or disk
    // is stuck, and a new call would only wait out its deadline.
    bool stalled(std::chrono::steady_clock::time_point now) const {
        return !busy_since.empty() &&
               std::all_of(busy_since.begin(), busy_since.end(), [&](const auto& since) {
                   return since && now - *since > options.deadline;
               });
    }

    void run(Call& call) const {
        const std::function<void(Session&)> body = [&call](Session& session) {
            std::unique_lock lock(call.mutex);
            if (call.abandoned)
                throw Abort{StoreStatus::unavailable, std::string(abandoned_detail)};
            GuardedSession guarded(session, call, lock);
            (*call.body)(guarded);
        };
        std::function<bool(Session&)> verify;
        if (call.verify != nullptr) {
            verify = [&call](Session& session) {
                std::unique_lock lock(call.mutex);
                if (call.abandoned) return false;
                GuardedSession guarded(session, call, lock);
                return (*call.verify)(guarded);
            };
        }
        std::string detail;
        const StoreStatus status = inner->transact(call.write, body, verify, detail);
        std::lock_guard lock(call.mutex);
        if (call.abandoned) return;
        call.status = status;
        call.detail = std::move(detail);
        call.done = true;
        call.finished.notify_one();
    }

    void serve(std::size_t index) {
        std::unique_lock lock(mutex);
        for (;;) {
            work.wait(lock, [&] { return stopping || !queue.empty(); });
            if (stopping) break;
            const std::shared_ptr<Call> call = std::move(queue.front());
            queue.pop_front();
            {
                // A call whose caller has gone is skipped.
                std::lock_guard call_lock(call->mutex);
                if (call->abandoned) continue;
            }
            busy_since[index] = std::chrono::steady_clock::now();
            lock.unlock();
            run(*call);
            lock.lock();
            busy_since[index].reset();
        }
        --running;
        exited.notify_all();
    }
};

StoreExecutor::StoreExecutor(std::unique_ptr<Backend> inner, ExecutorOptions options)
    : shared_(std::make_shared<Shared>()) {
    shared_->inner = std::move(inner);
    shared_->options = options;
    shared_->options.threads = std::max<std::size_t>(options.threads, 1);
    shared_->busy_since.resize(shared_->options.threads);
    shared_->running = shared_->options.threads;
    for (std::size_t i = 0; i < shared_->options.threads; ++i) {
        // Each thread keeps the shared state alive: a thread stuck in I/O at destruction is
        // left to finish on its own (see the destructor).
        threads_.emplace_back([shared = shared_, i] { shared->serve(i); });
    }
}

StoreExecutor::~StoreExecutor() {
    std::deque<std::shared_ptr<Call>> left;
    bool all_exited = false;
    {
        std::unique_lock lock(shared_->mutex);
        shared_->stopping = true;
        left.swap(shared_->queue);
        shared_->work.notify_all();
        // Threads between calls exit at once; one stuck on a frozen disk or a silent network
        // must not hold the service's shutdown: after a moment it is left behind (it holds
        // the shared state, so nothing it uses goes away).
        all_exited = shared_->exited.wait_for(lock, std::chrono::seconds(2),
                                              [&] { return shared_->running == 0; });
    }
    for (std::thread& thread : threads_) {
        if (all_exited) {
            thread.join();
        } else {
            thread.detach();
        }
    }
    for (const auto& call : left) {
        std::lock_guard lock(call->mutex);
        call->status = StoreStatus::unavailable;
        call->detail = "the store is closing";
        call->done = true;
        call->finished.notify_one();
    }
}

Dialect StoreExecutor::dialect() const { return shared_->inner->dialect(); }

void StoreExecutor::set_deadline(std::chrono::milliseconds deadline) {
    std::lock_guard lock(shared_->mutex);
    shared_->options.deadline = deadline;
}

StoreStatus StoreExecutor::transact(bool write, const std::function<void(Session&)>& body,
                                    const std::function<bool(Session&)>& verify,
                                    std::string& detail) {
    auto call = std::make_shared<Call>();
    call->write = write;
    call->body = &body;
    call->verify = verify ? &verify : nullptr;
    std::chrono::steady_clock::time_point until;
    {
        std::lock_guard lock(shared_->mutex);
        const auto now = std::chrono::steady_clock::now();
        until = now + shared_->options.deadline;
        if (shared_->stopping) {
            detail = "the store is closing";
            return StoreStatus::unavailable;
        }
        if (shared_->stalled(now)) {
            detail = stalled_detail;
            return StoreStatus::unavailable;
        }
        auto& queue = shared_->queue;
        if (queue.size() >= shared_->options.queue) {
            std::erase_if(queue, [](const std::shared_ptr<Call>& queued) {
                std::lock_guard call_lock(queued->mutex);
                return queued->abandoned;
            });
        }
        if (queue.size() >= shared_->options.queue) {
            detail = queue_full_detail;
            return StoreStatus::unavailable;
        }
        queue.push_back(call);
    }
    shared_->work.notify_one();
    std::unique_lock lock(call->mutex);
    if (!call->finished.wait_until(lock, until, [&] { return call->done; })) {
        // The body is never resumed after this (see the top); a write may still commit.
        call->abandoned = true;
        detail = deadline_detail;
        return StoreStatus::unavailable;
    }
    detail = std::move(call->detail);
    return call->status;
}

}  // namespace rollgap::service::store::detail
