#pragma once
// One structured (logfmt) log line per HTTP request:
//   request id=4f1c… method=POST route=/v1/roll-gap path=/v1/roll-gap status=200
//   duration_ms=0.84 in_bytes=2 out_bytes=1830 remote=127.0.0.1 key=ci-runner
// Never a body, never a header other than the request id, never the token.

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>

#include <spdlog/logger.h>

namespace rollgap::service {

struct RequestLogEntry {
    std::string_view id;
    std::string_view method;
    std::string_view route;  // the route-table pattern, or "unmatched"
    std::string_view path;   // as sent, quoted and shortened
    int status = 0;
    double seconds = 0.0;
    std::size_t in_bytes = 0;
    std::size_t out_bytes = 0;
    std::string_view remote;
    std::string_view key = "anonymous";  // the client key's name, never the key
};

std::string format_request_line(const RequestLogEntry& entry);
void log_request(spdlog::logger& logger, const RequestLogEntry& entry);

// The client's X-Request-Id if it is 1..128 characters of [A-Za-z0-9._:-], else a new one.
std::string request_id_from(std::string_view client_value);
std::string new_request_id();  // 16 lower-case hex digits

// A logfmt value: bare if safe, else double-quoted with \" \\ and \xNN escapes, at most
// `max_chars` characters of the input (then "…").
std::string logfmt_value(std::string_view text, std::size_t max_chars = 200);

}  // namespace rollgap::service
