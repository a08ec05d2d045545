#pragma once
// The completion callbacks' sender (docs/http-api.md, "Completion callbacks"): one thread per
// replica claims a due delivery from the store's outbox (docs/job-store.md, "Callbacks"), fixes
// its body at the first attempt (the job's summary document), POSTs it signed, and records the
// outcome: delivered on a 2xx, otherwise retried after a doubling backoff until the attempts
// run out. Deliveries queued by any replica are sent by whichever claims them; a replica that
// dies mid-attempt loses its lease and another attempts again (at least once, one delivery id).
// Nothing here is started when the server allows no callbacks.

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "service/http/service_state.h"

namespace rollgap::service::http {

class WebhookDeliverer {
public:
    explicit WebhookDeliverer(ServiceState& state) : state_(state) {}
    ~WebhookDeliverer() { stop(); }
    WebhookDeliverer(const WebhookDeliverer&) = delete;
    WebhookDeliverer& operator=(const WebhookDeliverer&) = delete;

    void start();  // nothing when --webhook-allow is empty
    void stop();   // an attempt in flight is cut (a failed attempt, retried); idempotent

    // How often the outbox is looked at when nothing was due (a read, no lock taken).
    static constexpr std::chrono::milliseconds poll_interval{250};
    // A claimed delivery's lease: longer than one attempt can take (--webhook-timeout-ms, at
    // most 20 s, cuts an attempt whatever the receiver does).
    static constexpr std::chrono::milliseconds lease{30'000};
    static constexpr std::chrono::seconds connect_timeout{2};
    static constexpr std::chrono::seconds io_timeout{5};

private:
    void loop();
    bool deliver_one();  // false: nothing was due (or the store is away)

    ServiceState& state_;
    std::mutex mutex_;
    std::condition_variable wake_;
    bool stopping_ = false;
    std::thread thread_;
};

}  // namespace rollgap::service::http
