#pragma once
// Client keys with scopes (issue 16). A key is `rg_<name>_<secret>`: it carries its name, so a
// request is matched to one line of the key file and the name goes into the request log and
// onto every stored-scenario version it writes. The key file (a mounted Secret, never the job
// store: authentication must not depend on the store) holds one line per key:
//
//   # NAME SHA256-OF-SECRET-HEX SCOPES
//   ci-runner 3f7a…e1 read,compute
//
// It is re-read when its modification time or size changes (checked at most once a second);
// a file that does not parse keeps the last good keys and is logged once. The old bearer
// token (--token-file, ROLLGAP_TOKEN) is a key named "token" with every scope.

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rollgap::service {

enum Scope : unsigned {
    scope_read = 1,     // GET of jobs and stored scenarios
    scope_compute = 2,  // analyses, POST /v1/jobs, DELETE /v1/jobs/{id}
    scope_write = 4,    // PUT and DELETE of stored scenarios
    scope_admin = 8,    // every scope
};
inline constexpr unsigned all_scopes = scope_read | scope_compute | scope_write | scope_admin;

std::string_view scope_name(Scope scope);
// "read,compute" → the bits; nullopt for an unknown or empty scope.
std::optional<unsigned> parse_scopes(std::string_view text);
std::string scopes_text(unsigned scopes);

// Lower-case hex SHA-256 of `text` (OpenSSL).
std::string sha256_hex(std::string_view text);

// A key's name: 1..32 of [a-z0-9.-]; the secret after the last `_` is hex.
bool valid_key_name(std::string_view name);

struct NewKey {
    std::string key;   // shown once
    std::string line;  // for the key file
};
// A new key for `name` with a 256-bit secret from OpenSSL's generator; nullopt if the name or
// the scopes are invalid.
std::optional<NewKey> new_key(std::string_view name, std::string_view scopes);

struct ClientIdentity {
    std::string name;
    unsigned scopes = 0;
    bool has(Scope scope) const { return (scopes & (scope | scope_admin)) != 0; }
};

struct KeyLine {
    std::string name;
    std::string hash;  // hex
    unsigned scopes = 0;
};
// The lines of a key file; an error names the line number (never its content).
std::optional<std::vector<KeyLine>> parse_key_file(std::string_view text, std::string& error);

class KeyRing {
public:
    KeyRing(std::optional<std::string> token, std::string key_file);

    // Whether requests need a key at all (a token or a key file is configured).
    bool enabled() const { return token_.has_value() || !path_.empty(); }
    // Loads the key file at start; an error for the start-up message.
    std::optional<std::string> load();
    // The client a bearer value names, if it is a known key (the file is re-read first if
    // it changed); nullopt for an unknown or wrong key.
    std::optional<ClientIdentity> identify(std::string_view bearer);

private:
    void reload_if_changed();

    std::optional<std::string> token_;
    std::filesystem::path path_;
    std::mutex mutex_;
    std::vector<KeyLine> keys_;
    std::chrono::steady_clock::time_point next_check_{};
    std::filesystem::file_time_type mtime_{};
    std::uintmax_t size_ = 0;
    bool bad_logged_ = false;
};

}  // namespace rollgap::service
