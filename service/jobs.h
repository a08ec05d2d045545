#pragma once
// Asynchronous jobs of the HTTP service: a bounded, in-memory store.
//
// A job is queued → running → succeeded | failed | cancelled. The store holds at most
// `max_jobs` jobs in any state; a finished job is kept for `retention` after it finished and
// then expires (it is purged on the next access of the store, so memory is bounded by
// max_jobs × the largest result even when nobody polls). Jobs live in the replica that
// accepted them: see the README's "Scaling out".

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "service/evaluate.h"

namespace rollgap::service {

enum class JobState { queued, running, succeeded, failed, cancelled };
std::string_view job_state_name(JobState state);

struct Job {
    using SteadyTime = std::chrono::steady_clock::time_point;
    using WallTime = std::chrono::system_clock::time_point;

    std::string id;
    std::string analysis;
    nlohmann::json request;  // the facade request; released when the job finishes
    SteadyTime deadline;

    std::atomic<bool> cancel_requested{false};
    std::atomic<double> progress{0.0};

    // Guarded by the store's mutex.
    JobState state = JobState::queued;
    WallTime created_at;
    std::optional<WallTime> started_at;
    std::optional<WallTime> finished_at;
    std::optional<SteadyTime> expires;  // set when finished
    std::optional<Outcome> outcome;     // set when succeeded or failed
};

struct JobCounts {
    std::size_t queued = 0, running = 0, succeeded = 0, failed = 0, cancelled = 0;
    std::size_t total() const { return queued + running + succeeded + failed + cancelled; }
    std::size_t active() const { return queued + running; }
};

enum class CancelResult {
    not_found,
    cancelled,         // it was queued: cancelled now, it will not run
    cancel_requested,  // it is running: its computation is told to stop
    deleted,           // it had finished: removed from the store
};

class JobStore {
public:
    using SteadyClock = std::function<Job::SteadyTime()>;

    JobStore(
        std::size_t max_jobs, std::chrono::milliseconds retention, std::string instance,
        SteadyClock clock = [] { return std::chrono::steady_clock::now(); });

    // A new queued job, or nullptr when the store is full (after purging expired jobs and,
    // oldest first, jobs cancelled by DELETE: a client that cancelled a job gave up its slot).
    std::shared_ptr<Job> create(std::string analysis, nlohmann::json request,
                                Job::SteadyTime deadline);

    // Removes a job that could not be queued after all.
    void remove(const std::string& id);

    // queued → running; false if the job was cancelled meanwhile (then it must not run).
    bool start(const std::shared_ptr<Job>& job);

    // running → succeeded / failed, or cancelled if cancellation was requested.
    void finish(const std::shared_ptr<Job>& job, Outcome outcome);

    // The job document (see the OpenAPI schema Job), or nothing if unknown or expired.
    std::optional<nlohmann::json> document(const std::string& id);

    // What DELETE does; `document` receives the job's document unless it was deleted, `job`
    // the job itself (to withdraw a queued job's task).
    CancelResult cancel(const std::string& id, nlohmann::json* document = nullptr,
                        std::shared_ptr<Job>* job = nullptr);

    // Requests cancellation of every queued or running job (drain timeout).
    void cancel_all();

    JobCounts counts();
    std::size_t capacity() const { return max_jobs_; }

private:
    void purge_expired();    // under mutex_
    bool evict_cancelled();  // under mutex_: the cancelled job that finished first
    nlohmann::json document_of(const Job& job) const;  // under mutex_
    void set_finished(Job& job, JobState state);       // under mutex_

    std::size_t max_jobs_;
    std::chrono::milliseconds retention_;
    std::string instance_;
    SteadyClock clock_;
    std::mutex mutex_;
    std::map<std::string, std::shared_ptr<Job>, std::less<>> jobs_;
};

// 32 lower-case hex digits from the operating system's random source.
std::string random_job_id();

// RFC 3339 UTC with milliseconds: 2024-05-01T12:34:56.789Z
std::string rfc3339(std::chrono::system_clock::time_point time);

}  // namespace rollgap::service
