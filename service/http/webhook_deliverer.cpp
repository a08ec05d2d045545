#include "service/http/webhook_deliverer.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <mutex>
#include <string>
#include <thread>

#include "service/jobs.h"
#include "service/version.h"
#include "service/webhooks.h"

namespace rollgap::service::http {

using nlohmann::json;

namespace webhook_deliverer_detail {

// Why an attempt got no answer, for the job document and the log.
std::string transport_error(httplib::Error error) {
    switch (error) {
        case httplib::Error::Connection: return "could not connect";
        case httplib::Error::ConnectionTimeout: return "connect timed out";
        case httplib::Error::Read: return "no answer (read failed or timed out)";
        case httplib::Error::Write: return "the request could not be sent";
        case httplib::Error::SSLConnection: return "TLS handshake failed";
        case httplib::Error::SSLServerVerification: return "TLS certificate not verified";
        default: return "no answer (" + httplib::to_string(error) + ")";
    }
}

}  // namespace webhook_deliverer_detail

void WebhookDeliverer::start() {
    if (state_.config.webhook_allow.empty() || !state_.config.webhook_secret) return;
    thread_ = std::thread([this] { loop(); });
}

void WebhookDeliverer::stop() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
}

void WebhookDeliverer::loop() {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
        lock.unlock();
        const bool attempted = deliver_one();
        lock.lock();
        if (attempted) continue;  // there may be more due
        wake_.wait_for(lock, poll_interval, [this] { return stopping_; });
    }
}

bool WebhookDeliverer::deliver_one() {
    auto store = state_.store.get();
    if (!store) return false;
    auto claimed = store->claim_delivery(state_.config.instance, lease);
    state_.store.report(claimed.status);
    if (!claimed.ok() || !claimed.value->has_value()) return false;
    const store::Delivery delivery = std::move(**claimed.value);

    // The body is fixed at the first attempt, so every retry sends the same bytes. A job
    // deleted or purged before it is announces its id and final state only.
    std::string body;
    if (delivery.body) {
        body = *delivery.body;
    } else {
        auto job = store->get(delivery.job_id);
        json document =
            job.ok() ? job_document(*job.value, state_.config.job_retention, JobDetail::summary)
                     : json{{"id", delivery.job_id},
                            {"state", store::job_state_name(delivery.job_state)}};
        body = webhook_body(delivery.id, std::move(document)).dump();
        const auto fixed = store->set_delivery_body(delivery, body);
        state_.store.report_write(fixed);
        if (fixed != store::StoreStatus::ok) return true;  // the lease is gone or the store away
    }

    const auto url = parse_webhook_url(delivery.url);
    std::string error;
    // An operator who took a prefix off the list (on this replica or all) expects no more calls
    // there: a delivery queued before is given up, not sent.
    const bool allowed = url && webhook_allowed(*url, state_.config.webhook_allow);
    if (!url) {
        error = "the callback URL no longer parses";
    } else if (!allowed) {
        error = "the callback URL is no longer under a prefix of --webhook-allow";
    } else {
        httplib::Client client(url->scheme + "://" + url->host + ":" + std::to_string(url->port));
        client.set_connection_timeout(connect_timeout);
        client.set_read_timeout(io_timeout);
        client.set_write_timeout(io_timeout);
        client.set_follow_location(false);
        const std::int64_t timestamp = store::system_millis() / 1000;
        const httplib::Headers headers = {
            {"Rollgap-Delivery", delivery.id},
            {"Rollgap-Event", "job.finished"},
            {"Rollgap-Timestamp", std::to_string(timestamp)},
            {"Rollgap-Signature",
             webhook_signature(*state_.config.webhook_secret, timestamp, body)},
            {"User-Agent", "rollgap/" + std::string(version())},
        };
        // The attempt as a whole ends at --webhook-timeout-ms, or when the deliverer stops: a
        // receiver that sends its answer a byte every few seconds passes every per-read
        // timeout and would hold this thread past the lease. The watchdog shuts the socket
        // (httplib's stop() is the thread-safe way), and Post returns; again until it has (a
        // stop() before Post opened its socket has nothing to shut yet).
        bool attempt_over = false;
        bool cut = false;
        std::thread watchdog([&] {
            std::unique_lock lock(mutex_);
            wake_.wait_for(lock, state_.config.webhook_timeout,
                           [&] { return attempt_over || stopping_; });
            while (!attempt_over) {
                cut = true;
                client.stop();
                wake_.wait_for(lock, std::chrono::milliseconds(50), [&] { return attempt_over; });
            }
        });
        const auto answer = client.Post(url->target(), headers, body, "application/json");
        {
            std::lock_guard lock(mutex_);
            attempt_over = true;
        }
        wake_.notify_all();
        watchdog.join();
        if (!answer) {
            error = cut ? "no complete answer within " +
                              std::to_string(state_.config.webhook_timeout.count()) +
                              " ms (--webhook-timeout-ms), or the replica was stopping"
                        : webhook_deliverer_detail::transport_error(answer.error());
        } else if (answer->status < 200 || answer->status > 299) {
            error = "HTTP " + std::to_string(answer->status);
        }
    }
    const std::int64_t made = delivery.attempts + 1;
    const auto outcome =
        error.empty() ? store::DeliveryOutcome::delivered
        : !allowed || made >= static_cast<std::int64_t>(state_.config.webhook_max_attempts)
            ? store::DeliveryOutcome::failed
            : store::DeliveryOutcome::retry;
    const store::Millis next_at =
        store::system_millis() + webhook_backoff(made, state_.config.webhook_backoff).count();
    const auto recorded = store->record_delivery(delivery, outcome, next_at, error);
    state_.store.report_write(recorded);
    const char* name = outcome == store::DeliveryOutcome::delivered ? "delivered"
                       : outcome == store::DeliveryOutcome::failed  ? "failed"
                                                                    : "retried";
    state_.metrics.count_webhook_delivery(name);
    // The origin only: a path or query may carry the receiver's own token.
    const std::string origin = url ? url->origin() : std::string("(unparsable)");
    if (outcome == store::DeliveryOutcome::delivered) {
        spdlog::info("callback delivered delivery={} job={} attempt={} to={}", delivery.id,
                     delivery.job_id, made, origin);
    } else {
        spdlog::warn("callback {} delivery={} job={} attempt={} to={} error=\"{}\"", name,
                     delivery.id, delivery.job_id, made, origin, error);
    }
    return true;
}

}  // namespace rollgap::service::http
