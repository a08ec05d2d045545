#pragma once
// What a job request carries besides the analysis (POST /v1/jobs, POST /v1/batches): the
// client's labels (a coil id, a line, an order: echoed, filterable in GET /v1/jobs?label=),
// how long the finished job is kept (retention_s, up to the server's maximum) and where its
// completion is announced (callback_url, under one of the server's allowed prefixes).

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "service/webhooks.h"

namespace rollgap::service {

inline constexpr std::size_t max_job_labels = 16;
inline constexpr std::size_t max_label_name = 63;
inline constexpr std::size_t max_label_value = 256;

struct JobSettings {
    std::vector<std::pair<std::string, std::string>> labels;  // by name
    std::optional<std::chrono::milliseconds> retention;       // nothing: the server's default
    std::optional<std::string> callback_url;                  // as given, allowed
};

// The server's rules for those members.
struct JobRules {
    std::chrono::milliseconds max_retention{86'400'000};
    std::span<const WebhookUrl> webhook_allow;  // empty: no callbacks on this server
};

// Takes `labels`, `retention_s` and `callback_url` out of `request` (what remains is the
// analysis' request) and checks them; every violation is recorded at its pointer
// (/labels/<name>, /retention_s, /callback_url).
JobSettings take_job_settings(nlohmann::json& request, const JobRules& rules,
                              api::FieldErrors& errors);

// A label filter of GET /v1/jobs: "name:value" (the value may hold ':'), or nothing when the
// name is not a label name.
std::optional<std::pair<std::string, std::string>> label_filter(std::string_view text);

// The labels as the job document shows them: {"name": "value", ...}.
nlohmann::json labels_json(const std::vector<std::pair<std::string, std::string>>& labels);

}  // namespace rollgap::service
