#include "service/jobs.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <ctime>
#include <random>

#include <spdlog/fmt/fmt.h>

namespace rollgap::service {

std::string_view job_state_name(JobState state) {
    switch (state) {
        case JobState::queued: return "queued";
        case JobState::running: return "running";
        case JobState::succeeded: return "succeeded";
        case JobState::failed: return "failed";
        case JobState::cancelled: return "cancelled";
    }
    return "unknown";
}

std::string random_job_id() {
    // random_device reads the kernel's CSPRNG here (glibc, Linux): ids are not guessable, so a
    // client cannot poll or cancel another client's job by counting.
    thread_local std::random_device device;
    std::string id;
    id.reserve(32);
    for (int i = 0; i < 4; ++i) id += fmt::format("{:08x}", static_cast<std::uint32_t>(device()));
    return id;
}

std::string rfc3339(std::chrono::system_clock::time_point time) {
    const auto since_epoch = time.time_since_epoch();
    const auto seconds = std::chrono::floor<std::chrono::seconds>(since_epoch);
    const auto millis =
        std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - seconds).count();
    const std::time_t t = static_cast<std::time_t>(seconds.count());
    std::tm utc{};
    gmtime_r(&t, &utc);
    std::array<char, 32> text{};
    const std::size_t n = std::strftime(text.data(), text.size(), "%Y-%m-%dT%H:%M:%S", &utc);
    return fmt::format("{}.{:03d}Z", std::string_view(text.data(), n), static_cast<int>(millis));
}

JobStore::JobStore(std::size_t max_jobs, std::chrono::milliseconds retention, std::string instance,
                   SteadyClock clock)
    : max_jobs_(max_jobs), retention_(retention), instance_(std::move(instance)),
      clock_(std::move(clock)) {}

void JobStore::purge_expired() {
    const auto now = clock_();
    std::erase_if(jobs_, [now](const auto& entry) {
        const Job& job = *entry.second;
        return job.expires && *job.expires <= now;
    });
}

bool JobStore::evict_cancelled() {
    auto oldest = jobs_.end();
    for (auto entry = jobs_.begin(); entry != jobs_.end(); ++entry) {
        const Job& job = *entry->second;
        if (job.state == JobState::cancelled &&
            (oldest == jobs_.end() || job.finished_at < oldest->second->finished_at)) {
            oldest = entry;
        }
    }
    if (oldest == jobs_.end()) return false;
    jobs_.erase(oldest);
    return true;
}

std::shared_ptr<Job> JobStore::create(std::string analysis, nlohmann::json request,
                                      Job::SteadyTime deadline) {
    std::lock_guard lock(mutex_);
    purge_expired();
    if (jobs_.size() >= max_jobs_ && !evict_cancelled()) return nullptr;
    auto job = std::make_shared<Job>();
    do {
        job->id = random_job_id();
    } while (jobs_.contains(job->id));
    job->analysis = std::move(analysis);
    job->request = std::move(request);
    job->deadline = deadline;
    job->created_at = std::chrono::system_clock::now();
    jobs_.emplace(job->id, job);
    return job;
}

void JobStore::remove(const std::string& id) {
    std::lock_guard lock(mutex_);
    jobs_.erase(id);
}

bool JobStore::start(const std::shared_ptr<Job>& job) {
    std::lock_guard lock(mutex_);
    if (job->state != JobState::queued) return false;  // cancelled while queued
    job->state = JobState::running;
    job->started_at = std::chrono::system_clock::now();
    return true;
}

void JobStore::set_finished(Job& job, JobState state) {
    job.state = state;
    job.finished_at = std::chrono::system_clock::now();
    job.expires = clock_() + retention_;
    job.request =
        nullptr;  // the scenario is echoed in the result; the request is not needed any more
}

void JobStore::finish(const std::shared_ptr<Job>& job, Outcome outcome) {
    std::lock_guard lock(mutex_);
    if (job->state != JobState::running) return;
    if (job->cancel_requested.load()) {
        set_finished(*job, JobState::cancelled);
        return;
    }
    const bool ok = outcome.ok();
    if (ok) job->progress = 1.0;
    job->outcome = std::move(outcome);
    set_finished(*job, ok ? JobState::succeeded : JobState::failed);
}

nlohmann::json JobStore::document_of(const Job& job) const {
    nlohmann::json document = {
        {"id", job.id},
        {"analysis", job.analysis},
        {"state", job_state_name(job.state)},
        {"progress", std::clamp(job.progress.load(), 0.0, 1.0)},
        {"instance", instance_},
        {"created_at", rfc3339(job.created_at)},
    };
    if (job.started_at) document["started_at"] = rfc3339(*job.started_at);
    if (job.finished_at) document["finished_at"] = rfc3339(*job.finished_at);
    if (job.expires) {
        // The wall-clock time of the steady expiry.
        const auto left = *job.expires - clock_();
        document["expires_at"] =
            rfc3339(std::chrono::system_clock::now() +
                    std::chrono::duration_cast<std::chrono::system_clock::duration>(left));
    }
    if (job.cancel_requested.load()) document["cancel_requested"] = true;
    if (job.outcome) {
        if (job.outcome->ok()) {
            document["result"] = job.outcome->body;
        } else {
            document["problem"] = job.outcome->body;
        }
    }
    return document;
}

std::optional<nlohmann::json> JobStore::document(const std::string& id) {
    std::lock_guard lock(mutex_);
    purge_expired();
    const auto found = jobs_.find(id);
    if (found == jobs_.end()) return std::nullopt;
    return document_of(*found->second);
}

CancelResult JobStore::cancel(const std::string& id, nlohmann::json* document,
                              std::shared_ptr<Job>* cancelled) {
    std::lock_guard lock(mutex_);
    purge_expired();
    const auto found = jobs_.find(id);
    if (found == jobs_.end()) return CancelResult::not_found;
    if (cancelled != nullptr) *cancelled = found->second;
    Job& job = *found->second;
    CancelResult result = CancelResult::deleted;
    switch (job.state) {
        case JobState::queued:
            job.cancel_requested = true;
            set_finished(job, JobState::cancelled);
            result = CancelResult::cancelled;
            break;
        case JobState::running:
            job.cancel_requested = true;
            result = CancelResult::cancel_requested;
            break;
        case JobState::succeeded:
        case JobState::failed:
        case JobState::cancelled: jobs_.erase(found); return CancelResult::deleted;
    }
    if (document != nullptr) *document = document_of(job);
    return result;
}

void JobStore::cancel_all() {
    std::lock_guard lock(mutex_);
    for (auto& [id, job] : jobs_) {
        if (job->state == JobState::queued) {
            job->cancel_requested = true;
            set_finished(*job, JobState::cancelled);
        } else if (job->state == JobState::running) {
            job->cancel_requested = true;
        }
    }
}

JobCounts JobStore::counts() {
    std::lock_guard lock(mutex_);
    purge_expired();
    JobCounts counts;
    for (const auto& [id, job] : jobs_) {
        switch (job->state) {
            case JobState::queued: ++counts.queued; break;
            case JobState::running: ++counts.running; break;
            case JobState::succeeded: ++counts.succeeded; break;
            case JobState::failed: ++counts.failed; break;
            case JobState::cancelled: ++counts.cancelled; break;
        }
    }
    return counts;
}

}  // namespace rollgap::service
