#include "service/request_log.h"

#include <cstdint>
#include <random>

#include <spdlog/fmt/fmt.h>

namespace rollgap::service {
namespace {

bool id_character(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
           c == '_' || c == ':' || c == '-';
}

bool bare_character(char c) {
    return id_character(c) || c == '/' || c == '{' || c == '}' || c == '?';
}

}  // namespace

std::string new_request_id() {
    // Not a secret, only unique enough to find a request in the logs: a per-thread generator
    // seeded once from the OS.
    thread_local std::mt19937_64 generator{std::random_device{}()};
    return fmt::format("{:016x}", generator());
}

std::string request_id_from(std::string_view client_value) {
    if (client_value.empty() || client_value.size() > 128) return new_request_id();
    for (const char c : client_value) {
        if (!id_character(c)) return new_request_id();
    }
    return std::string(client_value);
}

std::string logfmt_value(std::string_view text, std::size_t max_chars) {
    const bool shortened = text.size() > max_chars;
    if (shortened) text = text.substr(0, max_chars);
    bool bare = !text.empty() && !shortened;
    for (const char c : text) bare = bare && bare_character(c);
    if (bare) return std::string(text);
    std::string value = "\"";
    for (const char c : text) {
        const auto byte = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            value += '\\';
            value += c;
        } else if (byte < 0x20 || byte >= 0x7f) {
            value += fmt::format("\\x{:02x}", byte);
        } else {
            value += c;
        }
    }
    if (shortened) value += "...";
    value += '"';
    return value;
}

std::string format_request_line(const RequestLogEntry& entry) {
    return fmt::format(
        "request id={} method={} route={} path={} status={} duration_ms={:.3f} in_bytes={} "
        "out_bytes={} remote={} key={}",
        logfmt_value(entry.id), logfmt_value(entry.method, 16), logfmt_value(entry.route),
        logfmt_value(entry.path), entry.status, entry.seconds * 1e3, entry.in_bytes,
        entry.out_bytes, logfmt_value(entry.remote, 64), logfmt_value(entry.key, 40));
}

void log_request(spdlog::logger& logger, const RequestLogEntry& entry) {
    // Server errors are worth a warning; everything else is routine.
    const auto level =
        entry.status >= 500 && entry.status != 503 ? spdlog::level::warn : spdlog::level::info;
    if (!logger.should_log(level)) return;
    logger.log(level, "{}", format_request_line(entry));  // the line has braces: not a format
}

}  // namespace rollgap::service
