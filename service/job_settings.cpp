#include "service/job_settings.h"

#include <algorithm>

#include "api/json_pointer.h"
#include "api/text.h"

namespace rollgap::service {
namespace job_settings_detail {

using api::concat;

constexpr std::string_view name_rule = "1 to 63 of [A-Za-z0-9._-], starting with a letter or digit";

bool valid_name(std::string_view name) {
    if (name.empty() || name.size() > max_label_name) return false;
    const auto alnum = [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    };
    if (!alnum(name.front())) return false;
    return std::all_of(name.begin(), name.end(),
                       [&](char c) { return alnum(c) || c == '.' || c == '_' || c == '-'; });
}

// Printable text: no control characters (a line break would end a label in the store's form).
bool valid_value(std::string_view value) {
    return value.size() <= max_label_value && std::none_of(value.begin(), value.end(), [](char c) {
               const auto u = static_cast<unsigned char>(c);
               return u < 0x20 || u == 0x7f;
           });
}

void take_callback(const nlohmann::json& url, const JobRules& rules, JobSettings& settings,
                   api::FieldErrors& errors) {
    const std::string bound =
        concat("an http(s) URL of at most ", std::to_string(max_callback_url), " characters");
    if (rules.webhook_allow.empty()) {
        errors.add({"/callback_url",
                    "this server sends no completion callbacks (its operator allows none: "
                    "--webhook-allow); poll the job or follow GET /v1/jobs/{id}/events",
                    std::nullopt, std::nullopt});
        return;
    }
    const auto parsed =
        url.is_string() ? parse_webhook_url(url.get_ref<const std::string&>()) : std::nullopt;
    if (!parsed) {
        errors.add(
            {"/callback_url",
             concat("must be ", bound, ", without user information, fragment or dot segments"),
             bound, std::nullopt});
        return;
    }
    if (!webhook_allowed(*parsed, rules.webhook_allow)) {
        std::string allowed;
        for (const WebhookUrl& prefix : rules.webhook_allow)
            allowed += (allowed.empty() ? "" : ", ") + prefix.origin() + prefix.path;
        errors.add({"/callback_url",
                    concat("is not under a prefix this server may call (", allowed, ")"), allowed,
                    std::nullopt});
        return;
    }
    settings.callback_url = url.get<std::string>();
}

}  // namespace job_settings_detail

JobSettings take_job_settings(nlohmann::json& request, const JobRules& rules,
                              api::FieldErrors& errors) {
    namespace jd = job_settings_detail;
    using api::concat;
    JobSettings settings;
    if (!request.is_object()) return settings;
    if (const auto found = request.find("labels"); found != request.end()) {
        const nlohmann::json labels = std::move(*found);
        request.erase("labels");
        if (!labels.is_object() && !labels.is_null()) {
            errors.add({"/labels",
                        "must be an object of labels, each \"name\": \"value\" (e.g. \"coil\": "
                        "\"C-4711\")",
                        std::nullopt, std::nullopt});
        } else if (labels.is_object() && labels.size() > max_job_labels) {
            errors.add({"/labels", concat("at most ", std::to_string(max_job_labels), " labels"),
                        concat("0 to ", std::to_string(max_job_labels), " labels"), std::nullopt});
        } else if (labels.is_object()) {
            for (const auto& [name, value] : labels.items()) {
                const std::string pointer = concat("/labels/", api::escape_pointer_token(name));
                if (!jd::valid_name(name)) {
                    errors.add({pointer, concat("a label's name is ", jd::name_rule),
                                std::string(jd::name_rule), std::nullopt});
                } else if (!value.is_string()) {
                    errors.add(
                        {pointer, "a label's value is a string", std::nullopt, std::nullopt});
                } else if (!jd::valid_value(value.get_ref<const std::string&>())) {
                    errors.add(
                        {pointer,
                         concat("a label's value is at most ", std::to_string(max_label_value),
                                " characters without control characters"),
                         concat("0 to ", std::to_string(max_label_value), " characters"),
                         std::nullopt});
                } else {
                    settings.labels.emplace_back(name, value.get<std::string>());
                }
            }
        }
    }
    if (const auto found = request.find("retention_s"); found != request.end()) {
        const nlohmann::json retention = std::move(*found);
        request.erase("retention_s");
        const long long max_s = rules.max_retention.count() / 1000;
        const std::string bound = concat("[1, ", std::to_string(max_s), "]");
        if (!retention.is_null()) {
            if (!retention.is_number_integer() || retention.get<long long>() < 1 ||
                retention.get<long long>() > max_s) {
                errors.add({"/retention_s",
                            concat("how long the finished job is kept: whole seconds in ", bound,
                                   " (the server's --max-job-retention-ms)"),
                            bound, "s"});
            } else {
                settings.retention = std::chrono::seconds(retention.get<long long>());
            }
        }
    }
    if (const auto found = request.find("callback_url"); found != request.end()) {
        const nlohmann::json url = std::move(*found);
        request.erase("callback_url");
        if (!url.is_null()) jd::take_callback(url, rules, settings, errors);
    }
    return settings;
}

std::optional<std::pair<std::string, std::string>> label_filter(std::string_view text) {
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos) return std::nullopt;
    const std::string_view name = text.substr(0, colon);
    if (!job_settings_detail::valid_name(name)) return std::nullopt;
    return std::pair{std::string(name), std::string(text.substr(colon + 1))};
}

nlohmann::json labels_json(const std::vector<std::pair<std::string, std::string>>& labels) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [name, value] : labels) out[name] = value;
    return out;
}

}  // namespace rollgap::service
