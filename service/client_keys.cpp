#include "service/client_keys.h"

#include <openssl/evp.h>
#include <openssl/rand.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>
#include <sstream>

#include <spdlog/spdlog.h>

namespace rollgap::service {
namespace {

constexpr std::array<std::pair<Scope, std::string_view>, 4> scope_names{{
    {scope_read, "read"},
    {scope_compute, "compute"},
    {scope_write, "write"},
    {scope_admin, "admin"},
}};

constexpr auto check_interval = std::chrono::seconds(1);

std::string hex(const unsigned char* data, std::size_t size) {
    static constexpr char digits[] = "0123456789abcdef";
    std::string text;
    text.reserve(2 * size);
    for (std::size_t i = 0; i < size; ++i) {
        text += digits[data[i] >> 4];
        text += digits[data[i] & 0xf];
    }
    return text;
}

bool is_hex(std::string_view text) {
    return std::all_of(text.begin(), text.end(),
                       [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); });
}

// Compares without an early exit, so the time does not tell how much of a hash matched.
bool constant_time_same(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    unsigned char difference = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        difference |= static_cast<unsigned char>(a[i] ^ b[i]);
    return difference == 0;
}

}  // namespace

std::string_view scope_name(Scope scope) {
    for (const auto& [bit, name] : scope_names) {
        if (bit == scope) return name;
    }
    return "unknown";
}

std::optional<unsigned> parse_scopes(std::string_view text) {
    unsigned scopes = 0;
    while (!text.empty()) {
        const auto comma = text.find(',');
        const std::string_view item = text.substr(0, comma);
        text = comma == std::string_view::npos ? std::string_view() : text.substr(comma + 1);
        const auto found = std::find_if(scope_names.begin(), scope_names.end(),
                                        [item](const auto& entry) { return entry.second == item; });
        if (found == scope_names.end()) return std::nullopt;
        scopes |= found->first;
    }
    if (scopes == 0) return std::nullopt;
    return scopes;
}

std::string scopes_text(unsigned scopes) {
    std::string text;
    for (const auto& [bit, name] : scope_names) {
        if ((scopes & bit) == 0) continue;
        if (!text.empty()) text += ',';
        text += name;
    }
    return text;
}

std::string sha256_hex(std::string_view text) {
    std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
    unsigned int length = 0;
    if (EVP_Digest(text.data(), text.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1)
        return {};
    return hex(digest.data(), length);
}

bool valid_key_name(std::string_view name) {
    return !name.empty() && name.size() <= 32 && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '.';
    });
}

std::optional<NewKey> new_key(std::string_view name, std::string_view scopes) {
    const auto bits = parse_scopes(scopes);
    if (!valid_key_name(name) || !bits) return std::nullopt;
    std::array<unsigned char, 32> secret{};
    if (RAND_bytes(secret.data(), static_cast<int>(secret.size())) != 1) return std::nullopt;
    const std::string secret_hex = hex(secret.data(), secret.size());
    NewKey key;
    key.key = "rg_" + std::string(name) + "_" + secret_hex;
    key.line = std::string(name) + " " + sha256_hex(secret_hex) + " " + scopes_text(*bits);
    return key;
}

std::optional<std::vector<KeyLine>> parse_key_file(std::string_view text, std::string& error) {
    std::vector<KeyLine> keys;
    std::istringstream lines{std::string(text)};
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        std::istringstream fields(line);
        KeyLine key;
        std::string scopes, extra;
        fields >> key.name >> key.hash >> scopes;
        const auto bits = parse_scopes(scopes);
        if (!valid_key_name(key.name) || key.hash.size() != 64 || !is_hex(key.hash) || !bits ||
            (fields >> extra)) {
            error = "line " + std::to_string(number) +
                    ": expected NAME SHA256HEX SCOPES (scopes: read, compute, write, admin)";
            return std::nullopt;
        }
        if (std::any_of(keys.begin(), keys.end(),
                        [&](const KeyLine& k) { return k.name == key.name; })) {
            error = "line " + std::to_string(number) + ": the name " + key.name + " again";
            return std::nullopt;
        }
        key.scopes = *bits;
        keys.push_back(std::move(key));
    }
    return keys;
}

KeyRing::KeyRing(std::optional<std::string> token, std::string key_file)
    : token_(std::move(token)), path_(std::move(key_file)) {}

std::optional<std::string> KeyRing::load() {
    if (path_.empty()) return std::nullopt;
    std::lock_guard lock(mutex_);
    std::error_code failed;
    const auto mtime = std::filesystem::last_write_time(path_, failed);
    const auto size = failed ? 0 : std::filesystem::file_size(path_, failed);
    std::ifstream file(path_, std::ios::binary);
    if (failed || !file) return "cannot read the key file " + path_.string();
    const std::string text{std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
    std::string error;
    auto keys = parse_key_file(text, error);
    if (!keys) return "the key file " + path_.string() + " is invalid: " + error;
    keys_ = std::move(*keys);
    mtime_ = mtime;
    size_ = size;
    next_check_ = std::chrono::steady_clock::now() + check_interval;
    return std::nullopt;
}

void KeyRing::reload_if_changed() {
    const auto now = std::chrono::steady_clock::now();
    if (path_.empty() || now < next_check_) return;
    next_check_ = now + check_interval;
    std::error_code failed;
    const auto mtime = std::filesystem::last_write_time(path_, failed);
    const auto size = failed ? 0 : std::filesystem::file_size(path_, failed);
    if (!failed && mtime == mtime_ && size == size_) return;
    std::string error = "cannot read it";
    std::optional<std::vector<KeyLine>> keys;
    if (std::ifstream file(path_, std::ios::binary); !failed && file) {
        const std::string text{std::istreambuf_iterator<char>(file),
                               std::istreambuf_iterator<char>()};
        keys = parse_key_file(text, error);
    }
    if (!keys) {
        // A half-written or broken file must not lock everyone out: the last good keys stay.
        if (!bad_logged_) {
            spdlog::warn("key file {} not reloaded ({}); keeping the {} keys read before",
                         path_.string(), error, keys_.size());
            bad_logged_ = true;
        }
        return;
    }
    keys_ = std::move(*keys);
    mtime_ = mtime;
    size_ = size;
    bad_logged_ = false;
    spdlog::info("key file {} reloaded: {} keys", path_.string(), keys_.size());
}

std::optional<ClientIdentity> KeyRing::identify(std::string_view bearer) {
    if (token_ && constant_time_same(bearer, *token_)) return ClientIdentity{"token", all_scopes};
    if (path_.empty() || !bearer.starts_with("rg_")) return std::nullopt;
    const auto last = bearer.rfind('_');
    if (last <= 3) return std::nullopt;
    const std::string_view name = bearer.substr(3, last - 3);
    const std::string hash = sha256_hex(bearer.substr(last + 1));
    std::lock_guard lock(mutex_);
    reload_if_changed();
    for (const KeyLine& key : keys_) {
        if (key.name == name && constant_time_same(hash, key.hash))
            return ClientIdentity{key.name, key.scopes};
    }
    return std::nullopt;
}

}  // namespace rollgap::service
