#pragma once
// What a job request carries besides the analysis (POST /v1/jobs, POST /v1/batches): the
// client's labels (a coil id, a line, an order: echoed, filterable in GET /v1/jobs?label=) and
// how long the finished job is kept (retention_s, up to the server's maximum).

#include <chrono>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"

namespace rollgap::service {

inline constexpr std::size_t max_job_labels = 16;
inline constexpr std::size_t max_label_name = 63;
inline constexpr std::size_t max_label_value = 256;

struct JobSettings {
    std::vector<std::pair<std::string, std::string>> labels;  // by name
    std::optional<std::chrono::milliseconds> retention;       // nothing: the server's default
};

// Takes `labels` and `retention_s` out of `request` (what remains is the analysis' request)
// and checks them; every violation is recorded at its pointer (/labels/<name>, /retention_s).
JobSettings take_job_settings(nlohmann::json& request, std::chrono::milliseconds max_retention,
                              api::FieldErrors& errors);

// A label filter of GET /v1/jobs: "name:value" (the value may hold ':'), or nothing when the
// name is not a label name.
std::optional<std::pair<std::string, std::string>> label_filter(std::string_view text);

// The labels as the job document shows them: {"name": "value", ...}.
nlohmann::json labels_json(const std::vector<std::pair<std::string, std::string>>& labels);

}  // namespace rollgap::service
