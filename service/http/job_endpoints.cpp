#include "service/http/job_endpoints.h"

#include <algorithm>
#include <cmath>

#include "api/field_errors.h"
#include "api/text.h"
#include "service/evaluate.h"
#include "service/http/compute.h"
#include "service/http/responses.h"
#include "service/http/routes.h"

namespace rollgap::service::http {

using api::concat;
using nlohmann::json;

void JobEndpoints::create(json request, httplib::Response& response) {
    if (auto problem = check_envelope(request)) {
        set_json(response, problem->http_status, problem->body, problem->media_type());
        return;
    }
    if (state_.draining) {
        state_.overloaded(response, "the service is shutting down and accepts no new jobs");
        return;
    }
    std::string analysis = request["analysis"].get<std::string>();
    std::shared_ptr<Job> job = state_.jobs.create(std::move(analysis), std::move(request),
                                                  SteadyClock::now() + state_.config.job_deadline);
    if (!job) {
        state_.overloaded(response,
                          concat("the job store is full (", std::to_string(state_.jobs.capacity()),
                                 " jobs); retry later or DELETE finished jobs"));
        return;
    }
    if (!state_.pool.try_submit(
            Lane::batch, [this, job] { run(job); }, job.get())) {
        state_.jobs.remove(job->id);
        state_.overloaded(response, "the job queue is full; retry later");
        return;
    }
    response.set_header("Location", concat(jobs_prefix, job->id));
    if (auto document = state_.jobs.document(job->id)) {
        set_json(response, 202, *document, "application/json");
    } else {
        response.status = 202;  // already finished and expired (retention 0)
    }
}

void JobEndpoints::run(const std::shared_ptr<Job>& job) {
    if (!state_.jobs.start(job)) {
        state_.metrics.count_skipped("cancelled");
        return;
    }
    const auto late = [job] { return SteadyClock::now() >= job->deadline; };
    const auto cancelled = [job] { return job->cancel_requested.load(); };
    core::Control control = control_for(state_, [this, late, cancelled] {
        return cancelled() || late() || state_.hard_cancel.load();
    });
    control.progress = [job](double fraction) {
        if (std::isfinite(fraction)) job->progress = std::clamp(fraction, 0.0, 1.0);
    };
    Outcome outcome = compute(state_, job->request, control, late, cancelled);
    if (!cancelled() && (late() || state_.hard_cancel)) {
        outcome = problem_outcome(deadline_problem(state_.config.job_deadline));
    }
    state_.jobs.finish(job, std::move(outcome));
}

void JobEndpoints::get(const std::string& id, httplib::Response& response) {
    if (auto document = state_.jobs.document(id)) {
        set_json(response, 200, *document, "application/json");
    } else {
        not_found(id, response);
    }
}

void JobEndpoints::not_found(const std::string& id, httplib::Response& response) {
    set_problem(response, api::ProblemCode::not_found,
                concat("no job ", api::quoted_for_message(id),
                       " on this instance: it never existed, has expired or was deleted"));
}

void JobEndpoints::cancel(const std::string& id, httplib::Response& response) {
    json document;
    std::shared_ptr<Job> job;
    switch (state_.jobs.cancel(id, &document, &job)) {
        case CancelResult::not_found: not_found(id, response); return;
        case CancelResult::cancelled:
            // It will never run: its task leaves the batch lane now, not when a worker is free.
            state_.pool.withdraw(job.get());
            set_json(response, 200, document, "application/json");
            return;
        case CancelResult::cancel_requested:
            set_json(response, 202, document, "application/json");
            return;
        case CancelResult::deleted: response.status = 204; return;
    }
}

}  // namespace rollgap::service::http
