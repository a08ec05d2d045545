#include "service/webhooks.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>

#include <openssl/evp.h>
#include <openssl/hmac.h>

namespace rollgap::service {
namespace webhooks_detail {

std::string lower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool host_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '-';
}

bool ipv6_char(char c) {
    return (c >= 'a' && c <= 'f') || (c >= '0' && c <= '9') || c == ':' || c == '.';
}

// A path whose segments mean the same to every parser: no "." or ".." segment, no encoded dot
// (%2e), no backslash.
bool plain_path(std::string_view path) {
    if (lower(path).find("%2e") != std::string::npos) return false;
    if (path.find('\\') != std::string_view::npos) return false;
    std::size_t at = 0;
    while (at < path.size()) {
        const std::size_t next = path.find('/', at + 1);
        const std::string_view segment = path.substr(
            at + 1, next == std::string_view::npos ? std::string_view::npos : next - at - 1);
        if (segment == "." || segment == "..") return false;
        if (next == std::string_view::npos) break;
        at = next;
    }
    return true;
}

}  // namespace webhooks_detail

std::string WebhookUrl::origin() const {
    return scheme + "://" + host + ":" + std::to_string(port);
}

std::string WebhookUrl::target() const { return query.empty() ? path : path + "?" + query; }

std::string redacted_callback_url(std::string_view text) {
    if (!parse_webhook_url(text)) return "…";
    const std::size_t query = text.find('?');
    return query == std::string_view::npos ? std::string(text)
                                           : std::string(text.substr(0, query)) + "?…";
}

std::optional<WebhookUrl> parse_webhook_url(std::string_view text) {
    namespace wd = webhooks_detail;
    if (text.empty() || text.size() > max_callback_url) return std::nullopt;
    if (std::any_of(text.begin(), text.end(), [](char c) {
            const auto u = static_cast<unsigned char>(c);
            return u <= 0x20 || u >= 0x7f || c == '#';
        }))
        return std::nullopt;
    WebhookUrl url;
    const std::size_t colon = text.find("://");
    if (colon == std::string_view::npos) return std::nullopt;
    url.scheme = wd::lower(text.substr(0, colon));
    if (url.scheme != "http" && url.scheme != "https") return std::nullopt;
    std::string_view rest = text.substr(colon + 3);
    const std::size_t authority_end = rest.find_first_of("/?");
    const std::string_view authority = rest.substr(0, authority_end);
    rest =
        authority_end == std::string_view::npos ? std::string_view() : rest.substr(authority_end);
    if (authority.empty() || authority.find('@') != std::string_view::npos) return std::nullopt;
    std::string_view host = authority;
    std::string_view port;
    if (authority.front() == '[') {
        const std::size_t close = authority.find(']');
        if (close == std::string_view::npos) return std::nullopt;
        host = authority.substr(0, close + 1);
        const std::string_view after = authority.substr(close + 1);
        if (!after.empty()) {
            if (after.front() != ':') return std::nullopt;
            port = after.substr(1);
        }
        url.host = wd::lower(host);
        if (url.host.size() < 3 ||
            !std::all_of(url.host.begin() + 1, url.host.end() - 1, wd::ipv6_char))
            return std::nullopt;
    } else {
        const std::size_t port_colon = authority.find(':');
        if (port_colon != std::string_view::npos) {
            host = authority.substr(0, port_colon);
            port = authority.substr(port_colon + 1);
        }
        url.host = wd::lower(host);
        if (url.host.empty() || !std::all_of(url.host.begin(), url.host.end(), wd::host_char))
            return std::nullopt;
    }
    if (port.empty()) {
        url.port = url.scheme == "https" ? 443 : 80;
    } else {
        const auto [end, error] = std::from_chars(port.data(), port.data() + port.size(), url.port);
        if (error != std::errc{} || end != port.data() + port.size() || url.port < 1 ||
            url.port > 65535)
            return std::nullopt;
    }
    const std::size_t question = rest.find('?');
    url.path = std::string(rest.substr(0, question));
    if (question != std::string_view::npos) url.query = std::string(rest.substr(question + 1));
    if (url.path.empty()) url.path = "/";
    if (!wd::plain_path(url.path)) return std::nullopt;
    return url;
}

bool webhook_allowed(const WebhookUrl& url, std::span<const WebhookUrl> prefixes) {
    return std::any_of(prefixes.begin(), prefixes.end(), [&](const WebhookUrl& prefix) {
        if (url.scheme != prefix.scheme || url.host != prefix.host || url.port != prefix.port)
            return false;
        const std::string& p = prefix.path;
        if (!url.path.starts_with(p)) return false;
        return p.ends_with('/') || url.path.size() == p.size() || url.path[p.size()] == '/';
    });
}

std::string hmac_sha256_hex(std::string_view key, std::string_view message) {
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int length = 0;
    const unsigned char* out = HMAC(EVP_sha256(), key.data(), static_cast<int>(key.size()),
                                    reinterpret_cast<const unsigned char*>(message.data()),
                                    message.size(), digest.data(), &length);
    if (out == nullptr) return {};
    static constexpr std::string_view hex = "0123456789abcdef";
    std::string text;
    text.reserve(2 * length);
    for (unsigned int i = 0; i < length; ++i) {
        text += hex[digest[i] >> 4];
        text += hex[digest[i] & 0x0f];
    }
    return text;
}

std::string webhook_signature(std::string_view secret, std::int64_t timestamp_s,
                              std::string_view body) {
    std::string signed_text = std::to_string(timestamp_s);
    signed_text += '.';
    signed_text += body;
    return "v1=" + hmac_sha256_hex(secret, signed_text);
}

std::chrono::milliseconds webhook_backoff(std::int64_t made, std::chrono::milliseconds base) {
    std::chrono::milliseconds wait = base;
    for (std::int64_t i = 1; i < made && wait < max_webhook_backoff; ++i) wait *= 2;
    return std::min(wait, max_webhook_backoff);
}

nlohmann::json webhook_body(std::string_view delivery_id, nlohmann::json job_document) {
    return {{"event", "job.finished"},
            {"delivery_id", std::string(delivery_id)},
            {"job", std::move(job_document)}};
}

}  // namespace rollgap::service
