// The names and the clock job_store.h declares.

#include "service/store/job_store.h"

#include <array>
#include <chrono>

namespace rollgap::service::store {

std::string_view status_name(StoreStatus status) {
    switch (status) {
        case StoreStatus::ok: return "ok";
        case StoreStatus::not_found: return "not_found";
        case StoreStatus::conflict: return "conflict";
        case StoreStatus::invalid: return "invalid";
        case StoreStatus::full: return "full";
        case StoreStatus::unavailable: return "unavailable";
    }
    return "unknown";
}

std::string_view stored_kind_name(StoredKind kind) {
    return kind == StoredKind::mill ? "mill" : "stand";
}

namespace {
constexpr std::array<std::string_view, 5> state_names = {"queued", "running", "succeeded", "failed",
                                                         "cancelled"};
}

std::string_view job_state_name(JobState state) {
    return state_names.at(static_cast<std::size_t>(state));
}

std::optional<JobState> job_state_from_name(std::string_view name) {
    for (std::size_t i = 0; i < state_names.size(); ++i) {
        if (state_names[i] == name) return static_cast<JobState>(i);
    }
    return std::nullopt;
}

Millis system_millis() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace rollgap::service::store
