#pragma once
// Completion callbacks (webhooks) without HTTP: which URLs a job may name (the operator's
// allow-list of URL prefixes, matched on the parsed scheme, host, port and path, never on the
// text), how a delivery is signed (HMAC-SHA256 over "timestamp.body") and when a failed
// attempt is tried again. The deliverer that sends them is service/http/webhook_deliverer.h;
// docs/http-api.md ("Completion callbacks") is the receiver's side.

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace rollgap::service {

inline constexpr std::size_t max_callback_url = 2048;

// A URL parsed into what the allow-list compares: http or https, a host (lower case, an IPv6
// address in brackets), the port (the scheme's when absent), the path ("/" when absent) and the
// query (without '?'). No user information, fragment, dot segment, encoded dot, backslash or
// control character: a URL whose meaning could differ between this parser and a receiver's is
// refused rather than guessed.
struct WebhookUrl {
    std::string scheme;
    std::string host;
    int port = 0;
    std::string path;
    std::string query;

    std::string origin() const;  // "https://mes.plant.example:443": for logs, no path or query
    std::string target() const;  // path and query: what the request line carries
};
std::optional<WebhookUrl> parse_webhook_url(std::string_view text);

// A callback URL as documents show it: scheme, host, port and path, the query (where a
// receiver's token often rides) replaced by "?…". Text that does not parse is shown as "…".
std::string redacted_callback_url(std::string_view text);

// Whether `url` lies under one of `prefixes`: the same scheme, host and port, and a path that is
// the prefix's path or continues it at a segment boundary ("/hooks" admits "/hooks" and
// "/hooks/rollgap", not "/hooks-evil"; "/hooks/" admits what starts with it).
bool webhook_allowed(const WebhookUrl& url, std::span<const WebhookUrl> prefixes);

// HMAC-SHA256 of `message` under `key`, 64 lower-case hex digits (RFC 2104, FIPS 180-4).
std::string hmac_sha256_hex(std::string_view key, std::string_view message);

// The Rollgap-Signature header: "v1=" and the HMAC of "<timestamp>.<body>" under the secret.
std::string webhook_signature(std::string_view secret, std::int64_t timestamp_s,
                              std::string_view body);

// When attempt `made + 1` is due after `made` failed ones: base · 2^(made-1), at most 5 min.
std::chrono::milliseconds webhook_backoff(std::int64_t made, std::chrono::milliseconds base);
inline constexpr std::chrono::milliseconds max_webhook_backoff{300'000};

// The body of a delivery: {"event": "job.finished", "delivery_id": ..., "job": <the job's
// summary document>}.
nlohmann::json webhook_body(std::string_view delivery_id, nlohmann::json job_document);

}  // namespace rollgap::service
