#include "service/http/store_handle.h"

#include <spdlog/spdlog.h>

#include "service/config.h"

namespace rollgap::service::http {

StoreHandle::StoreHandle(std::string setting, store::StoreLimits limits)
    : setting_(std::move(setting)), limits_(limits) {}

std::shared_ptr<store::JobStore> StoreHandle::get() {
    std::lock_guard lock(mutex_);
    if (store_) return store_;
    const auto now = std::chrono::steady_clock::now();
    if (now < next_attempt_) return nullptr;
    next_attempt_ = now + retry_interval;
    auto opened = store::open_store(setting_, limits_);
    if (!opened.ok()) {
        // The detail never holds the DSN (open_store keeps it out).
        if (!down_logged_.exchange(true)) {
            spdlog::warn("job store {} unavailable ({}): {}; jobs and stored scenarios answer 503",
                         redacted_store(setting_), store::status_name(opened.status),
                         opened.detail);
        }
        return nullptr;
    }
    store_ = std::move(*opened.value);
    down_logged_ = false;
    if (!up_.exchange(true)) spdlog::info("job store {} open", redacted_store(setting_));
    return store_;
}

void StoreHandle::report(store::StoreStatus status) {
    if (status == store::StoreStatus::unavailable) {
        if (up_.exchange(false))
            spdlog::warn(
                "job store unavailable; jobs and stored scenarios answer 503 until it answers again");
    } else if (!up_.exchange(true)) {
        spdlog::info("job store available again");
    }
}

}  // namespace rollgap::service::http
