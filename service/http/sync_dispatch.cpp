#include "service/http/sync_dispatch.h"

#include <condition_variable>
#include <optional>

#include "api/text.h"
#include "service/http/compute.h"
#include "service/http/responses.h"

namespace rollgap::service::http {

using nlohmann::json;

struct SyncCall {
    std::mutex mutex;
    std::condition_variable done;
    std::optional<Outcome> outcome;      // under mutex
    bool stopped = false;                // under mutex: the drain answered it
    std::atomic<bool> abandoned{false};  // the connection thread answered and left
    SteadyClock::time_point deadline;

    void complete(Outcome result) {
        {
            std::lock_guard lock(mutex);
            outcome = std::move(result);
        }
        done.notify_one();
    }
};

namespace {

class InFlight {
public:
    explicit InFlight(std::atomic<int>& counter) : counter_(counter) { ++counter_; }
    ~InFlight() { --counter_; }
    InFlight(const InFlight&) = delete;
    InFlight& operator=(const InFlight&) = delete;

private:
    std::atomic<int>& counter_;
};

constexpr std::string_view stopped_detail =
    "the service is shutting down; the analysis was stopped before it finished";

// The answer of a request stopped for `reason`: 503 at the drain (retry on another replica),
// 504 otherwise.
Outcome stopped_outcome(const ServiceState& state, StopReason reason) {
    if (reason == StopReason::shutdown) {
        return problem_outcome(
            api::make_problem(api::ProblemCode::overloaded, std::string(stopped_detail)));
    }
    return problem_outcome(deadline_problem(state.config.deadline));
}

void answer_stopped(ServiceState& state, StopReason reason, httplib::Response& response) {
    if (reason == StopReason::shutdown) {
        state.overloaded(response, std::string(stopped_detail));
    } else {
        set_problem(response, deadline_problem(state.config.deadline));
    }
}

}  // namespace

void SyncDispatch::run(const httplib::Request& http_request, json request, PreparedRequest ready,
                       SteadyClock::time_point arrival, httplib::Response& response,
                       const Answer& answer) {
    InFlight counted(state_.in_flight);
    auto call = std::make_shared<SyncCall>();
    call->deadline = arrival + state_.config.deadline;
    {
        std::lock_guard lock(mutex_);
        waiting_.insert(call);
    }
    struct Unregister {
        SyncDispatch& self;
        std::shared_ptr<SyncCall> call;
        ~Unregister() {
            std::lock_guard lock(self.mutex_);
            self.waiting_.erase(call);
        }
    } unregister{*this, call};

    ServiceState& state = state_;
    // The facade computes the request prepared here; an injected evaluator gets its JSON.
    if (is_facade(state_.evaluator)) request = nullptr;
    const bool queued = state_.pool.try_submit(
        Lane::interactive,
        [&state, call, request = std::move(request), ready = std::move(ready)]() mutable {
            const auto stopped = [&state, call] {
                return stop_reason({.shutdown = state.hard_cancel.load(std::memory_order_relaxed),
                                    .late = SteadyClock::now() >= call->deadline,
                                    .abandoned = call->abandoned.load(std::memory_order_relaxed)});
            };
            if (const StopReason reason = stopped(); reason != StopReason::none) {
                // Taken too late: complete it now so that nobody waits for it.
                state.metrics.count_skipped(reason == StopReason::shutdown ? "cancelled"
                                                                           : "deadline_exceeded");
                call->complete(stopped_outcome(state, reason));
                return;
            }
            const core::Control control =
                control_for(state, [stopped] { return stopped() != StopReason::none; });
            const auto work = [&]() -> Outcome {
                if (!request.is_null()) return state.evaluator(request, control);
                return service::run(std::move(ready), control);
            };
            call->complete(compute(state, ready.analysis->name, work, [&] {
                // Abandoned alone is no reason for the metrics: the connection thread left
                // because the deadline passed or the drain stopped it.
                return stop_reason({.shutdown = state.hard_cancel.load(),
                                    .late = SteadyClock::now() >= call->deadline});
            }));
        });
    if (!queued) {
        state_.overloaded(response, api::concat("every worker is busy and ",
                                                std::to_string(state_.config.queue_length),
                                                " requests are waiting; retry later"));
        return;
    }
    std::unique_lock lock(call->mutex);
    const bool answered = call->done.wait_until(
        lock, call->deadline, [&] { return call->outcome.has_value() || call->stopped; });
    if (!call->outcome) {
        call->abandoned = true;
        // Woken without an outcome: the drain stopped it; otherwise the deadline passed.
        answer_stopped(state_, stop_reason({.shutdown = answered && call->stopped, .late = true}),
                       response);
        return;
    }
    const Outcome& outcome = *call->outcome;
    if (outcome.problem == api::ProblemCode::cancelled ||
        outcome.problem == api::ProblemCode::overloaded) {
        // The facade cannot say why it was stopped (evaluate.h): its Control stops only at
        // the drain or the deadline.
        answer_stopped(state_, stop_reason({.shutdown = state_.hard_cancel.load(), .late = true}),
                       response);
        return;
    }
    if (answer && outcome.ok()) {
        answer(outcome, response);
        return;
    }
    set_outcome(http_request, outcome, response);
}

void SyncDispatch::stop_all() {
    std::lock_guard lock(mutex_);
    for (const auto& call : waiting_) {
        {
            std::lock_guard call_lock(call->mutex);
            call->stopped = true;
        }
        call->done.notify_one();
    }
}

}  // namespace rollgap::service::http
