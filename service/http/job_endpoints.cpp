#include "service/http/job_endpoints.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <thread>

#include "api/text.h"
#include "service/analyses/table.h"
#include "service/chunked.h"
#include "service/evaluate.h"
#include "service/http/responses.h"
#include "service/http/routes.h"
#include "service/http/listener.h"
#include "service/http/scenario_base.h"
#include "service/job_settings.h"
#include "service/jobs.h"

namespace rollgap::service::http {

using api::concat;
using nlohmann::json;

namespace {

// When to poll an unfinished job again, in seconds (Retry-After on its 202 and on a GET while
// it is queued or running): a stand's analysis takes tens of milliseconds to seconds.
constexpr std::string_view poll_hint_s = "1";

bool valid_idempotency_key(const std::string& key) {
    return !key.empty() && key.size() <= JobEndpoints::max_idempotency_key &&
           std::all_of(key.begin(), key.end(), [](char c) { return c > ' ' && c < 0x7f; });
}

}  // namespace

std::shared_ptr<store::JobStore> JobEndpoints::store_or_503(httplib::Response& response) {
    auto store = state_.store.get();
    if (!store) state_.store_unavailable(response, "the job store is unavailable; retry later");
    return store;
}

void JobEndpoints::store_failure(store::StoreStatus status, const std::string& id,
                                 httplib::Response& response) {
    state_.store.report(status);
    switch (status) {
        case store::StoreStatus::not_found: not_found(id, response); return;
        case store::StoreStatus::unavailable:
            state_.store_unavailable(response, "the job store is unavailable; retry later");
            return;
        default:
            set_problem(
                response, api::ProblemCode::internal,
                concat("the job store refused the operation (", store::status_name(status), ")"));
            return;
    }
}

void JobEndpoints::create(json request, const std::string& idempotency_key,
                          httplib::Response& response) {
    // The job's own members (labels, retention_s) are the job's, not the analysis': taken out
    // first; the hash below is of the body as sent, so they are part of the submission.
    const std::string sent = request.dump();  // object keys sorted: the canonical text
    api::FieldErrors job_errors;
    const JobSettings settings = take_job_settings(
        request, {state_.config.max_job_retention, state_.config.webhook_allow}, job_errors);
    if (!job_errors.empty()) {
        set_problem(response,
                    job_errors.to_problem(api::ProblemCode::invalid_request,
                                          concat(std::to_string(job_errors.size()), " violation",
                                                 job_errors.size() == 1 ? "" : "s",
                                                 " in the job's labels, retention or callback")));
        return;
    }
    if (auto problem = check_envelope(request)) {
        set_json(response, problem->http_status, problem->body, problem->media_type());
        return;
    }
    // Plant units in canonical keys before a stored base is merged under them; the stored
    // request is canonical (every replica reads it the same way).
    if (auto problem = canonicalise_units(request)) {
        set_json(response, problem->http_status, problem->body, problem->media_type());
        return;
    }
    if (state_.draining) {
        state_.overloaded(response, "the service is shutting down and accepts no new jobs");
        return;
    }
    if (!idempotency_key.empty() && !valid_idempotency_key(idempotency_key)) {
        set_problem(response, api::ProblemCode::invalid_request,
                    concat("the Idempotency-Key header must be 1 to ",
                           std::to_string(max_idempotency_key), " visible ASCII characters"));
        return;
    }
    auto store = store_or_503(response);
    if (!store) return;
    // The idempotency hash is of the body as sent: a retry after the stored scenario changed
    // is still the same submission (it returns the job made from the first).
    // A "base" is resolved now, so the stored request is self-contained: any replica, at any
    // time, computes it against the version the client was answered with.
    if (auto refused = resolve_base(request, state_)) {
        answer_unresolved(state_, *refused, response);
        return;
    }
    // The whole request is checked now, as a synchronous one is: an invalid scenario or options
    // is a 422 at once and nothing is stored. The prepared request is not kept: the job runs
    // from its stored JSON on any replica and is prepared again there (DECISIONS R).
    auto prepared = prepare(request);
    if (auto* problem = std::get_if<Outcome>(&prepared)) {
        set_json(response, problem->http_status, problem->body, problem->media_type());
        return;
    }
    const PreparedRequest& ready = std::get<PreparedRequest>(prepared);
    store::NewJob job;
    job.analysis = request["analysis"].get<std::string>();
    job.request = request.dump();
    const bool batch = ready.analysis->subject() == Subject::batch;
    job.deadline_ms = store::system_millis() +
                      (batch ? state_.config.batch_deadline : state_.config.job_deadline).count();
    job.instance = state_.config.instance;
    if (!idempotency_key.empty()) job.idempotency_key = idempotency_key;
    job.body_hash = body_hash(sent);
    job.labels = settings.labels;
    std::sort(job.labels.begin(), job.labels.end());
    if (settings.retention) job.retention_ms = settings.retention->count();
    job.callback_url = settings.callback_url;
    // A sweep or map is stored as chunks of points that workers on any replica claim.
    if (ready.prepared.points && ready.prepared.points->count > 0) {
        job.points = ready.prepared.points->count;
        job.chunk_size =
            static_cast<std::int64_t>(std::max<std::size_t>(state_.config.chunk_points, 1));
        // Every chunk parses and checks the whole stored batch: at most max_batch_chunks of
        // them, so a batch of 10,000 items is not parsed 400 times.
        if (batch)
            job.chunk_size =
                std::max(job.chunk_size, (job.points + max_batch_chunks - 1) / max_batch_chunks);
    }
    const auto created = store->create(job);
    state_.store.report_write(created.status);
    switch (created.status) {
        case store::StoreStatus::ok: break;
        case store::StoreStatus::full:
            state_.overloaded(
                response, concat("the job store is full (", std::to_string(state_.config.max_jobs),
                                 " jobs); retry later or DELETE finished jobs"));
            return;
        case store::StoreStatus::conflict:
            set_problem(response, api::ProblemCode::conflict,
                        "the Idempotency-Key was used for a job with another request body");
            return;
        case store::StoreStatus::unavailable:
            if (created.detail == store::deadline_detail) {
                // The insert may still commit after the deadline.
                state_.store_unavailable(
                    response,
                    "the job store did not answer in time: the outcome is unknown; retry with "
                    "the same Idempotency-Key (without one, a retry may create a second job)");
                return;
            }
            store_failure(created.status, "", response);
            return;
        default: store_failure(created.status, "", response); return;
    }
    const store::JobRecord& record = created.value->job;
    if (created.value->created) runner_.wake();
    response.set_header("Location", concat(jobs_prefix, record.id));
    if (created.value->created) response.set_header("Retry-After", std::string(poll_hint_s));
    set_json(response, created.value->created ? 202 : 200, full_document(*store, record),
             "application/json");
}

std::optional<store::JobRecord> JobEndpoints::live_job(store::JobStore& store,
                                                       const std::string& id,
                                                       httplib::Response& response) {
    auto found = store.get(id);
    if (!found.ok()) {
        store_failure(found.status, id, response);
        return std::nullopt;
    }
    state_.store.report(found.status);
    if (job_expired(*found.value, state_.config.job_retention, store::system_millis())) {
        not_found(id, response);
        return std::nullopt;
    }
    return std::move(*found.value);
}

void JobEndpoints::get(const httplib::Request& request, const std::string& id,
                       httplib::Response& response) {
    auto store = store_or_503(response);
    if (!store) return;
    const auto found = live_job(*store, id, response);
    if (!found) return;
    Outcome document;
    document.body = full_document(*store, *found);
    if (found->state == store::JobState::queued || found->state == store::JobState::running)
        response.set_header("Retry-After", std::string(poll_hint_s));
    set_outcome(request, document, response);
}

json JobEndpoints::full_document(store::JobStore& store, const store::JobRecord& job) {
    json document = job_document(job, state_.config.job_retention, JobDetail::full);
    if (job.points <= 0) return document;
    const json request = json::parse(job.request, nullptr, false);
    if (job.state == store::JobState::succeeded && document.contains("result")) {
        // The store keeps the concatenated point documents; the answer is assembled on read
        // (docs/job-store.md): the same bytes evaluate() gives in one process.
        const Outcome assembled = assemble_points(request, document["result"]);
        document.erase("result");
        document[assembled.ok() ? "result" : "problem"] = assembled.body;
    } else if (job.state != store::JobState::succeeded && job.points_done > 0) {
        // Running, or ended without its whole result (cancelled, failed): the points finished.
        const auto finished = store.finished_chunks(job.id);
        state_.store.report(finished.status);
        if (finished.ok()) {
            std::vector<std::pair<std::int64_t, json>> chunks;
            for (const store::ChunkResult& chunk : *finished.value)
                chunks.emplace_back(chunk.begin, json::parse(chunk.result, nullptr, false));
            document["partial_result"] = partial_result(job.points, chunks);
        }
    }
    return document;
}

void JobEndpoints::list(const httplib::Request& request, httplib::Response& response) {
    store::ListQuery query;
    query.limit = default_page;
    if (request.has_param("state")) {
        const std::string name = request.get_param_value("state");
        query.state = store::job_state_from_name(name);
        if (!query.state) {
            invalid_parameter(response, "state",
                              "one of queued, running, succeeded, failed, cancelled");
            return;
        }
    }
    // A job carries at most max_job_labels labels: more filters cannot all match.
    if (request.get_param_value_count("label") > max_job_labels) {
        invalid_parameter(response, "label",
                          concat("at most ", std::to_string(max_job_labels),
                                 " label filters (a job carries at most as many labels)"));
        return;
    }
    for (std::size_t i = 0; i < request.get_param_value_count("label"); ++i) {
        const auto filter = label_filter(request.get_param_value("label", i));
        if (!filter) {
            invalid_parameter(response, "label",
                              "name:value, the name 1 to 63 of [A-Za-z0-9._-] (repeat for all of "
                              "several labels)");
            return;
        }
        query.labels.push_back(*filter);
    }
    if (!read_page_limit(request, response, max_page, query.limit)) return;
    if (request.has_param("cursor")) query.cursor = request.get_param_value("cursor");
    auto store = store_or_503(response);
    if (!store) return;
    const auto page = store->list(query);
    if (page.status == store::StoreStatus::invalid) {
        state_.store.report(page.status);
        invalid_parameter(response, "cursor", "the next_cursor of an earlier page");
        return;
    }
    if (!page.ok()) {
        store_failure(page.status, "", response);
        return;
    }
    state_.store.report(page.status);
    json jobs = json::array();
    const auto now = store::system_millis();
    for (const store::JobRecord& job : page.value->jobs) {
        if (job_expired(job, state_.config.job_retention, now)) continue;
        jobs.push_back(job_document(job, state_.config.job_retention, JobDetail::summary));
    }
    json body = {{"jobs", std::move(jobs)}};
    if (page.value->next_cursor) body["next_cursor"] = *page.value->next_cursor;
    set_json(response, 200, body, "application/json");
}

void JobEndpoints::not_found(const std::string& id, httplib::Response& response) {
    set_problem(response, api::ProblemCode::not_found,
                concat("no job ", api::quoted_for_message(id),
                       ": it never existed, has expired or was deleted"));
}

void JobEndpoints::cancel(const std::string& id, httplib::Response& response) {
    auto store = store_or_503(response);
    if (!store) return;
    // One answer for every case: 200 and the job after the request. A finished job's is its
    // document as it was read here, marked deleted.
    const auto before = store->get(id);
    if (!before.ok()) {
        store_failure(before.status, id, response);
        return;
    }
    const auto cancelled = store->cancel(id);
    if (!cancelled.ok()) {
        store_failure(cancelled.status, id, response);
        return;
    }
    state_.store.report(cancelled.status);
    if (*cancelled.value == store::CancelResult::deleted) {
        json document = full_document(*store, *before.value);
        document["deleted"] = true;
        set_json(response, 200, document, "application/json");
        return;
    }
    // Running: the worker hears it at its next renewal wherever it runs; here at once.
    if (*cancelled.value == store::CancelResult::cancel_requested) runner_.cancel_local(id);
    const auto after = store->get(id);
    if (!after.ok()) {
        store_failure(after.status, id, response);
        return;
    }
    set_json(response, 200, full_document(*store, *after.value), "application/json");
}

// How often an event stream looks at its job in the store.
constexpr std::chrono::milliseconds event_poll{250};

void JobEndpoints::events(const std::string& id, httplib::Response& response) {
    auto store = store_or_503(response);
    if (!store) return;
    const auto found = live_job(*store, id, response);
    if (!found) return;
    // Each stream holds a connection thread for as long as it lasts: a bounded number.
    if (open_streams_->fetch_add(1) >= state_.config.max_event_streams) {
        open_streams_->fetch_sub(1);
        state_.overloaded(response,
                          concat("already ", std::to_string(state_.config.max_event_streams),
                                 " event streams open; poll GET /v1/jobs/{id} instead"));
        return;
    }
    struct Stream {
        std::string last;  // the last document sent
        bool ended = false;
    };
    auto stream = std::make_shared<Stream>();
    response.status = 200;
    response.set_header("Cache-Control", "no-cache");
    response.set_header("X-Accel-Buffering", "no");  // nginx passes each event at once
    const auto heartbeat = state_.config.event_heartbeat;
    response.set_chunked_content_provider(
        "text/event-stream",
        [this, id, stream, heartbeat](std::size_t, httplib::DataSink& sink) {
            const auto send = [&](const std::string& text) {
                restart_write_deadline();
                return sink.write(text.data(), text.size());
            };
            if (stream->ended) {
                sink.done();
                return true;
            }
            const auto quiet_until = std::chrono::steady_clock::now() + heartbeat;
            for (;;) {
                if (state_.draining) {  // the replica stops: the client reconnects elsewhere
                    stream->ended = true;
                    if (!send("event: end\ndata: {\"reason\": \"draining\"}\n\n")) return false;
                    sink.done();
                    return true;
                }
                auto current = state_.store.get();
                const auto read = current ? current->get(id)
                                          : store::Result<store::JobRecord>::failure(
                                                store::StoreStatus::unavailable, "");
                if (read.status == store::StoreStatus::not_found) {
                    stream->ended = true;
                    if (!send("event: end\ndata: {\"reason\": \"deleted\"}\n\n")) return false;
                    sink.done();
                    return true;
                }
                if (read.ok()) {
                    const json document =
                        job_document(*read.value, state_.config.job_retention, JobDetail::summary);
                    std::string text =
                        document.dump(-1, ' ', false, json::error_handler_t::replace);
                    if (text != stream->last) {
                        stream->last = text;
                        const bool finished = read.value->finished_ms.has_value();
                        std::string event = concat("event: job\ndata: ", text, "\n\n");
                        if (finished) {
                            stream->ended = true;
                            event += "event: end\ndata: {\"reason\": \"finished\"}\n\n";
                        }
                        return send(event);
                    }
                }
                if (std::chrono::steady_clock::now() >= quiet_until)
                    return send(": keep-alive\n\n");
                std::this_thread::sleep_for(event_poll);
            }
        },
        [streams = open_streams_](bool) { streams->fetch_sub(1); });
}

}  // namespace rollgap::service::http
