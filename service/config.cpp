#include "service/config.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "api/name_suggestion.h"
#include "api/text.h"
#include "service/cpu_quota.h"

namespace rollgap::service {
namespace {

using api::concat;

constexpr std::array settings{
    ConfigSetting{"--bind", "ROLLGAP_BIND", "ADDRESS",
                  "address to listen on (default 127.0.0.1; the container image sets 0.0.0.0)"},
    ConfigSetting{"--port", "ROLLGAP_PORT", "N", "TCP port, 0 for any free port (default 8080)"},
    ConfigSetting{
        "--admin-bind", "ROLLGAP_ADMIN_BIND", "ADDRESS",
        "address of the admin listener (/livez, /readyz, /metrics on threads of their own; "
        "default 127.0.0.1)"},
    ConfigSetting{
        "--admin-port", "ROLLGAP_ADMIN_PORT", "N",
        "TCP port of the admin listener, 0 for any free port (default 8081; with --port 0, 0)"},
    ConfigSetting{"--workers", "ROLLGAP_WORKERS", "N",
                  "compute threads, the one pool of the process (default: the CPUs the process "
                  "may use: cgroup quota, affinity mask)"},
    ConfigSetting{"--queue-length", "ROLLGAP_QUEUE_LENGTH", "N",
                  "synchronous requests that may wait for a worker; beyond: 503 (default 64)"},
    ConfigSetting{
        "--io-threads", "ROLLGAP_IO_THREADS", "N",
        "HTTP connection threads, one per open connection; keep above workers + queue-length "
        "(default 128)"},
    ConfigSetting{
        "--analysis-threads", "ROLLGAP_ANALYSIS_THREADS", "N",
        "workers of the pool one analysis may spread its scan speeds or sweep points over, its "
        "own included (default 0: all workers; at most the workers)"},
    ConfigSetting{"--deadline-ms", "ROLLGAP_DEADLINE_MS", "MS",
                  "time budget of a synchronous request; past it: 504 (default 30000)"},
    ConfigSetting{"--read-deadline-ms", "ROLLGAP_READ_DEADLINE_MS", "MS",
                  "a request's headers and body must arrive within this time from its first byte; "
                  "past it: 408 and the connection closes (default 10000)"},
    ConfigSetting{"--job-deadline-ms", "ROLLGAP_JOB_DEADLINE_MS", "MS",
                  "time budget of an asynchronous job (default 600000)"},
    ConfigSetting{"--job-retention-ms", "ROLLGAP_JOB_RETENTION_MS", "MS",
                  "how long a finished job is kept for polling, unless the job asks for another "
                  "retention_s (default 600000)"},
    ConfigSetting{"--max-job-retention-ms", "ROLLGAP_MAX_JOB_RETENTION_MS", "MS",
                  "the longest retention a job may ask for (retention_s); above: 422 (default "
                  "86400000)"},
    ConfigSetting{"--max-jobs", "ROLLGAP_MAX_JOBS", "N",
                  "jobs queued or running at once; beyond: 503 (default 256)"},
    ConfigSetting{"--max-finished-jobs", "ROLLGAP_MAX_FINISHED_JOBS", "N",
                  "finished jobs kept at once; beyond, the oldest finished go first, whatever "
                  "their retention (default 1000)"},
    ConfigSetting{"--max-event-streams", "ROLLGAP_MAX_EVENT_STREAMS", "N",
                  "GET /v1/jobs/{id}/events streams open at once; beyond: 503 (default 32)"},
    ConfigSetting{"--event-heartbeat-ms", "ROLLGAP_EVENT_HEARTBEAT_MS", "MS",
                  "longest silence on an event stream: a comment line is sent then (default "
                  "10000; proxies time out after 60 s)"},
    ConfigSetting{"--job-workers", "ROLLGAP_JOB_WORKERS", "N",
                  "workers that jobs may occupy at once (default max(1, workers/2))"},
    ConfigSetting{"--retry-after", "ROLLGAP_RETRY_AFTER", "S",
                  "Retry-After of a 503, seconds (default 1)"},
    ConfigSetting{"--drain-timeout-ms", "ROLLGAP_DRAIN_TIMEOUT_MS", "MS",
                  "on SIGTERM/SIGINT, how long in-flight work may finish before it is cancelled "
                  "(default 25000)"},
    ConfigSetting{"--max-body-bytes", "ROLLGAP_MAX_BODY_BYTES", "N",
                  "largest request body; beyond: 413 (default 1048576)"},
    ConfigSetting{"--max-batch-body-bytes", "ROLLGAP_MAX_BATCH_BODY_BYTES", "N",
                  "largest body of POST /v1/batches (up to 10,000 items); beyond: 413 (default "
                  "8388608)"},
    ConfigSetting{"--batch-deadline-ms", "ROLLGAP_BATCH_DEADLINE_MS", "MS",
                  "time budget of a batch job, from creation (default 3600000)"},
    ConfigSetting{"--log-level", "ROLLGAP_LOG_LEVEL", "LEVEL",
                  "trace, debug, info, warn, error, critical or off (default info)"},
    ConfigSetting{"", "ROLLGAP_TOKEN", "TOKEN",
                  "the bearer token itself (environment only: a flag would show in ps)"},
    ConfigSetting{"--token-file", "ROLLGAP_TOKEN_FILE", "PATH",
                  "file holding the bearer token required by the compute endpoints"},
    ConfigSetting{"--key-file", "ROLLGAP_KEY_FILE", "PATH",
                  "client keys with scopes, one 'NAME SHA256HEX SCOPES' line each (rollgap key "
                  "new); re-read within a second of a change"},
    ConfigSetting{"--allowed-hosts", "ROLLGAP_ALLOWED_HOSTS", "NAMES",
                  "comma-separated Host names served, * for any; others: 421 (default: when bound "
                  "to loopback, the bind address, localhost, 127.0.0.1 and ::1; else any)"},
    ConfigSetting{"--allowed-origins", "ROLLGAP_ALLOWED_ORIGINS", "ORIGINS",
                  "comma-separated browser origins (scheme://host[:port]) allowed to call the "
                  "API besides the service's own: CORS answers them (a browser HMI on another "
                  "origin), and they may POST, PUT, PATCH or DELETE; others: 403 (default none)"},
    ConfigSetting{"--webhook-allow", "ROLLGAP_WEBHOOK_ALLOW", "PREFIXES",
                  "comma-separated URL prefixes (https://host[:port]/path) a job's callback_url "
                  "may lie under; others: 422 (default none: no callbacks)"},
    ConfigSetting{"--webhook-secret-file", "ROLLGAP_WEBHOOK_SECRET_FILE", "PATH",
                  "file holding the secret that signs callbacks (HMAC-SHA256, Rollgap-Signature); "
                  "required with --webhook-allow"},
    ConfigSetting{"--webhook-backoff-ms", "ROLLGAP_WEBHOOK_BACKOFF_MS", "MS",
                  "wait after a callback's first failed attempt, doubling after each, at most 5 "
                  "min (default 1000)"},
    ConfigSetting{"--webhook-max-attempts", "ROLLGAP_WEBHOOK_MAX_ATTEMPTS", "N",
                  "attempts at a callback before it is given up (default 10)"},
    ConfigSetting{"--webhook-timeout-ms", "ROLLGAP_WEBHOOK_TIMEOUT_MS", "MS",
                  "longest a callback attempt may take, connect to answer, however its receiver "
                  "dribbles; then it is a failed attempt (default 15000, below the 30 s lease)"},
    ConfigSetting{"--max-scenarios", "ROLLGAP_MAX_SCENARIOS", "N",
                  "stored scenarios at once; a new name beyond: 507 (default 1000)"},
    ConfigSetting{"--instance", "ROLLGAP_INSTANCE", "NAME",
                  "this replica's name in job documents (default: the host name)"},
    ConfigSetting{"--data-dir", "ROLLGAP_DATA_DIR", "DIR",
                  "directory of the embedded job store (default rollgap-data; the container "
                  "image sets /var/lib/rollgap)"},
    ConfigSetting{"--store", "ROLLGAP_STORE", "SETTING",
                  "job store: sqlite:PATH, postgresql://USER@HOST:PORT/DB or "
                  "postgresql-file:PATH (a file holding the DSN) (default sqlite:DIR/jobs.db)"},
    ConfigSetting{"--lease-ms", "ROLLGAP_LEASE_MS", "MS",
                  "lease of a claimed job or chunk, renewed while it runs; a replica that dies "
                  "loses its work to the others after this long (default 15000)"},
    ConfigSetting{"--chunk-points", "ROLLGAP_CHUNK_POINTS", "N",
                  "sweep points or map cells per work item that one replica claims (default 25)"},
    ConfigSetting{"--store-connections", "ROLLGAP_STORE_CONNECTIONS", "N",
                  "threads of the job store, each with at most one database connection: a "
                  "replica opens at most this many PostgreSQL connections (default 4)"},
    ConfigSetting{"--store-deadline-ms", "ROLLGAP_STORE_DEADLINE_MS", "MS",
                  "how long a job or scenario request waits for the job store; past it: 503 "
                  "store_unavailable (default 2000)"},
};

// The numeric settings: the range a value must lie in and where it goes.
struct IntegerSetting {
    std::string_view env;
    long long min;
    long long max;
    std::string_view expected;  // the range, as the error message states it
    void (*store)(ServerConfig&, long long);
};

using std::chrono::milliseconds;
using std::chrono::seconds;

constexpr std::array integer_settings{
    IntegerSetting{"ROLLGAP_PORT", 0, 65535, "a port 0..65535",
                   [](ServerConfig& c, long long n) { c.port = static_cast<int>(n); }},
    IntegerSetting{"ROLLGAP_ADMIN_PORT", 0, 65535, "a port 0..65535",
                   [](ServerConfig& c, long long n) {
                       c.admin_port = static_cast<int>(n);
                       c.admin_port_set = true;
                   }},
    IntegerSetting{"ROLLGAP_WORKERS", 0, 1024, "0..1024 (0: the CPUs the process may use)",
                   [](ServerConfig& c, long long n) { c.workers = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_QUEUE_LENGTH", 0, 100000, "0..100000",
        [](ServerConfig& c, long long n) { c.queue_length = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_IO_THREADS", 1, 4096, "1..4096",
        [](ServerConfig& c, long long n) { c.io_threads = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_ANALYSIS_THREADS", 0, 1024, "0..1024 (0: all workers)",
        [](ServerConfig& c, long long n) { c.analysis_threads = static_cast<std::size_t>(n); }},
    IntegerSetting{"ROLLGAP_DEADLINE_MS", 1, 3'600'000, "1..3600000 ms",
                   [](ServerConfig& c, long long n) { c.deadline = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_READ_DEADLINE_MS", 100, 600'000, "100..600000 ms",
                   [](ServerConfig& c, long long n) { c.read_deadline = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_JOB_DEADLINE_MS", 1, 86'400'000, "1..86400000 ms",
                   [](ServerConfig& c, long long n) { c.job_deadline = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_JOB_RETENTION_MS", 0, 604'800'000, "0..604800000 ms",
                   [](ServerConfig& c, long long n) { c.job_retention = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_MAX_JOB_RETENTION_MS", 1000, 604'800'000, "1000..604800000 ms",
                   [](ServerConfig& c, long long n) { c.max_job_retention = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_MAX_JOBS", 0, 1'000'000, "0..1000000",
                   [](ServerConfig& c, long long n) { c.max_jobs = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_MAX_FINISHED_JOBS", 1, 1'000'000, "1..1000000",
        [](ServerConfig& c, long long n) { c.max_finished_jobs = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_MAX_EVENT_STREAMS", 0, 4096, "0..4096",
        [](ServerConfig& c, long long n) { c.max_event_streams = static_cast<std::size_t>(n); }},
    IntegerSetting{"ROLLGAP_EVENT_HEARTBEAT_MS", 100, 15'000, "100..15000 ms",
                   [](ServerConfig& c, long long n) { c.event_heartbeat = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_WEBHOOK_BACKOFF_MS", 10, 300'000, "10..300000 ms",
                   [](ServerConfig& c, long long n) { c.webhook_backoff = milliseconds(n); }},
    IntegerSetting{
        "ROLLGAP_WEBHOOK_MAX_ATTEMPTS", 1, 100, "1..100",
        [](ServerConfig& c, long long n) { c.webhook_max_attempts = static_cast<std::size_t>(n); }},
    IntegerSetting{"ROLLGAP_WEBHOOK_TIMEOUT_MS", 100, 20'000, "100..20000 ms",
                   [](ServerConfig& c, long long n) { c.webhook_timeout = milliseconds(n); }},
    IntegerSetting{
        "ROLLGAP_MAX_SCENARIOS", 1, 1'000'000, "1..1000000",
        [](ServerConfig& c, long long n) { c.max_scenarios = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_JOB_WORKERS", 0, 1024, "0..1024 (0: max(1, workers/2))",
        [](ServerConfig& c, long long n) { c.job_workers = static_cast<std::size_t>(n); }},
    IntegerSetting{"ROLLGAP_RETRY_AFTER", 0, 3600, "0..3600 s",
                   [](ServerConfig& c, long long n) { c.retry_after = seconds(n); }},
    IntegerSetting{"ROLLGAP_DRAIN_TIMEOUT_MS", 0, 3'600'000, "0..3600000 ms",
                   [](ServerConfig& c, long long n) { c.drain_timeout = milliseconds(n); }},
    IntegerSetting{
        "ROLLGAP_MAX_BODY_BYTES", 1024, 64LL * 1024 * 1024, "1024..67108864 bytes",
        [](ServerConfig& c, long long n) { c.max_body_bytes = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_MAX_BATCH_BODY_BYTES", 1024, 256LL * 1024 * 1024, "1024..268435456 bytes",
        [](ServerConfig& c, long long n) { c.max_batch_body_bytes = static_cast<std::size_t>(n); }},
    IntegerSetting{"ROLLGAP_BATCH_DEADLINE_MS", 1, 86'400'000, "1..86400000 ms",
                   [](ServerConfig& c, long long n) { c.batch_deadline = milliseconds(n); }},
    IntegerSetting{"ROLLGAP_LEASE_MS", 500, 3'600'000, "500..3600000 ms",
                   [](ServerConfig& c, long long n) { c.lease = milliseconds(n); }},
    IntegerSetting{
        "ROLLGAP_CHUNK_POINTS", 1, 100'000, "1..100000",
        [](ServerConfig& c, long long n) { c.chunk_points = static_cast<std::size_t>(n); }},
    IntegerSetting{
        "ROLLGAP_STORE_CONNECTIONS", 1, 64, "1..64",
        [](ServerConfig& c, long long n) { c.store_connections = static_cast<std::size_t>(n); }},
    IntegerSetting{"ROLLGAP_STORE_DEADLINE_MS", 10, 600'000, "10..600000 ms",
                   [](ServerConfig& c, long long n) { c.store_deadline = milliseconds(n); }},
};

std::optional<long long> parse_integer(std::string_view text, long long min, long long max) {
    long long value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (parsed.ec != std::errc() || parsed.ptr != text.data() + text.size()) return std::nullopt;
    if (value < min || value > max) return std::nullopt;
    return value;
}

std::string trim_trailing_newlines(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    return text;
}

std::string_view trimmed_view(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())))
        text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
        text.remove_suffix(1);
    return text;
}

bool loopback_address(std::string_view address) {
    return address.starts_with("127.") || address == "::1" || address == "[::1]" ||
           address == "localhost";
}

bool valid_log_level(std::string_view level) {
    static constexpr std::array<std::string_view, 7> levels{"trace", "debug",    "info", "warn",
                                                            "error", "critical", "off"};
    return std::find(levels.begin(), levels.end(), level) != levels.end();
}

// Applies one setting; returns an error message or nothing. `source` names where the value
// came from, for the message.
std::optional<std::string> apply(ServerConfig& config, const ConfigSetting& setting,
                                 const std::string& value, std::string_view source) {
    const auto bad = [&](std::string_view expected) {
        return concat("invalid ", source, " '", value, "': expected ", expected);
    };
    const std::string_view env = setting.env;
    const auto numeric = std::find_if(integer_settings.begin(), integer_settings.end(),
                                      [env](const IntegerSetting& s) { return s.env == env; });
    if (numeric != integer_settings.end()) {
        const auto n = parse_integer(value, numeric->min, numeric->max);
        if (!n) return bad(numeric->expected);
        numeric->store(config, *n);
        return std::nullopt;
    }
    if (env == "ROLLGAP_BIND") {
        if (value.empty()) return bad("an address");
        config.bind_address = value;
    } else if (env == "ROLLGAP_ADMIN_BIND") {
        if (value.empty()) return bad("an address");
        config.admin_bind_address = value;
    } else if (env == "ROLLGAP_LOG_LEVEL") {
        if (!valid_log_level(value)) return bad("trace, debug, info, warn, error, critical or off");
        config.log_level = value;
    } else if (env == "ROLLGAP_TOKEN_FILE") {
        std::ifstream file(value, std::ios::binary);
        if (!file) return concat("cannot read the token file named by ", source);
        std::string token = trim_trailing_newlines(
            std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()));
        if (token.empty()) return concat("the token file named by ", source, " is empty");
        config.token = std::move(token);
    } else if (env == "ROLLGAP_WEBHOOK_SECRET_FILE") {
        std::ifstream file(value, std::ios::binary);
        if (!file) return concat("cannot read the webhook secret file named by ", source);
        std::string secret = trim_trailing_newlines(
            std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()));
        if (secret.size() < 16)
            return concat("the webhook secret in the file named by ", source,
                          " must be at least 16 characters");
        config.webhook_secret = std::move(secret);
    } else if (env == "ROLLGAP_WEBHOOK_ALLOW") {
        config.webhook_allow.clear();
        std::string_view rest = value;
        while (!rest.empty()) {
            const auto comma = rest.find(',');
            const std::string_view item = trimmed_view(rest.substr(0, comma));
            rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
            if (item.empty()) continue;
            const auto prefix = parse_webhook_url(item);
            if (!prefix || !prefix->query.empty())
                return concat("invalid ", source, " entry '", item,
                              "': expected URL prefixes like https://host[:port]/path, "
                              "comma-separated (no query, user information or dot segments)");
            config.webhook_allow.push_back(*prefix);
        }
    } else if (env == "ROLLGAP_KEY_FILE") {
        if (value.empty()) return bad("a file");
        config.key_file = value;
    } else if (env == "ROLLGAP_ALLOWED_HOSTS" || env == "ROLLGAP_ALLOWED_ORIGINS") {
        std::vector<std::string> items;
        std::string_view rest = value;
        while (!rest.empty()) {
            const auto comma = rest.find(',');
            std::string item(trimmed_view(rest.substr(0, comma)));
            rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
            if (item.empty()) continue;
            for (char& c : item) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            if (env == "ROLLGAP_ALLOWED_ORIGINS" && !item.starts_with("http://") &&
                !item.starts_with("https://"))
                return bad("origins like https://host or http://host:port, comma-separated");
            while (env == "ROLLGAP_ALLOWED_ORIGINS" && item.ends_with('/')) item.pop_back();
            items.push_back(std::move(item));
        }
        (env == "ROLLGAP_ALLOWED_HOSTS" ? config.allowed_hosts : config.allowed_origins) =
            std::move(items);
    } else if (env == "ROLLGAP_DATA_DIR") {
        if (value.empty()) return bad("a directory");
        config.data_dir = value;
    } else if (env == "ROLLGAP_STORE") {
        // The value may be a DSN with a password: never echoed in a message.
        if (!value.starts_with("sqlite:") && !value.starts_with("postgresql://") &&
            !value.starts_with("postgres://") && !value.starts_with("postgresql-file:")) {
            return concat("invalid ", source,
                          ": expected sqlite:PATH, postgresql://… or postgresql-file:PATH");
        }
        config.store = value;
    } else if (env == "ROLLGAP_INSTANCE") {
        if (value.empty() || value.size() > 64) return bad("1..64 characters");
        config.instance = value;
    }
    return std::nullopt;
}

std::string host_name() {
    std::array<char, 256> name{};
    if (gethostname(name.data(), name.size() - 1) != 0) return "rollgap";
    return name.data();
}

std::string join(const std::vector<std::string>& items) {
    std::string text;
    for (const std::string& item : items) text += (text.empty() ? "" : ",") + item;
    return text;
}

}  // namespace

std::span<const ConfigSetting> config_settings() { return settings; }

ServerConfig ServerConfig::resolved() const {
    ServerConfig config = *this;
    // One pool for requests, jobs and the analyses' inner loops, as large as the CPUs the
    // process may really use (service/worker_pool.h says why).
    if (config.cpu_budget.empty()) {
        const CpuBudget cpus = service::cpu_budget();
        config.cpu_budget = describe(cpus);
        if (config.workers == 0) config.workers = static_cast<std::size_t>(cpus.effective);
    }
    if (config.workers == 0) config.workers = 1;
    if (config.analysis_threads == 0 || config.analysis_threads > config.workers)
        config.analysis_threads = config.workers;
    if (config.job_workers == 0) config.job_workers = std::max<std::size_t>(1, config.workers / 2);
    config.job_workers = std::min(config.job_workers, config.workers);
    if (config.instance.empty()) config.instance = host_name();
    if (config.store.empty()) config.store = concat("sqlite:", config.data_dir, "/jobs.db");
    // A service on loopback is reachable from the browsers of this machine only: a DNS name
    // rebound to 127.0.0.1 would hand a foreign page its answers, unless Host is checked.
    if (config.allowed_hosts.empty() && loopback_address(config.bind_address)) {
        config.allowed_hosts = {config.bind_address, "localhost", "127.0.0.1", "::1"};
    }
    // Instances started on any free port (tests, side-by-side runs) must not all claim 8081.
    if (config.port == 0 && !config.admin_port_set) config.admin_port = 0;
    return config;
}

void add_server_options(CLI::App& command, ServerConfig& config) {
    // Unknown arguments are collected, not refused by CLI11: its message would echo every
    // argument, and a value after a mistyped "--token" is a secret (finish_server_config).
    command.allow_extras();
    for (const ConfigSetting& setting : settings) {
        if (setting.flag.empty())
            continue;  // environment only: its own rule in finish_server_config
        const std::string source = concat(setting.flag, " (or ", setting.env, ")");
        command
            .add_option_function<std::string>(
                std::string(setting.flag),
                [&config, &setting, source](const std::string& value) {
                    if (auto error = apply(config, setting, value, source))
                        throw CLI::ValidationError(*error);
                },
                std::string(setting.help))
            ->envname(std::string(setting.env))
            ->type_name(std::string(setting.value));
    }
}

std::optional<std::string> finish_server_config(const CLI::App& command, ServerConfig& config) {
    if (const std::vector<std::string> extras = command.remaining(); !extras.empty()) {
        // Name the first one only, and an option without its "=value": no secret reaches the log.
        const std::string_view first = extras.front();
        if (!first.starts_with('-')) return concat("unexpected argument (rollgap serve --help)");
        const std::string_view name = first.substr(0, first.find('='));
        std::vector<std::string_view> flags;
        for (const ConfigSetting& setting : settings) {
            if (!setting.flag.empty()) flags.push_back(setting.flag);
        }
        return concat("unknown option '", name, "'", api::did_you_mean(name, flags),
                      " (rollgap serve --help)");
    }
    if (!config.webhook_allow.empty() && !config.webhook_secret)
        return std::string(
            "--webhook-allow needs --webhook-secret-file (or ROLLGAP_WEBHOOK_SECRET_FILE): "
            "callbacks are always signed");
    // The token: a file (--token-file or ROLLGAP_TOKEN_FILE) wins over ROLLGAP_TOKEN, which has
    // no flag because a secret on the command line shows in ps.
    if (config.token) return std::nullopt;
    if (const char* token = std::getenv("ROLLGAP_TOKEN")) {
        // Never echo the value in a message.
        if (*token == '\0') return std::string("ROLLGAP_TOKEN is set but empty");
        config.token = token;
    }
    return std::nullopt;
}

std::variant<ServerConfig, ConfigHelp, std::string> parse_server_config(
    std::span<const std::string_view> arguments) {
    ServerConfig config;
    CLI::App command("rollgap serve", "rollgap serve");
    add_server_options(command, config);
    // CLI11 takes the arguments last first.
    std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
    try {
        command.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        return ConfigHelp{};
    } catch (const CLI::ParseError& error) {
        return std::string(error.what());  // a value the table refuses: the table's message
    }
    if (auto error = finish_server_config(command, config)) return *error;
    return config;
}

std::string config_usage() {
    std::ostringstream text;
    text << "usage: rollgap serve [OPTION VALUE]...\n"
            "\n"
            "Serves the analyses over HTTP (REST API v1, OpenAPI document at /openapi.json).\n"
            "Each option is also read from an environment variable; a flag wins.\n"
            "SIGTERM or SIGINT drains: /readyz answers 503, in-flight work finishes, exit 0.\n"
            "\n";
    for (const ConfigSetting& setting : settings) {
        const std::string flag = setting.flag.empty() ? std::string("(env only)")
                                                      : concat(setting.flag, " ", setting.value);
        text << "  " << flag << std::string(flag.size() < 24 ? 24 - flag.size() : 1, ' ')
             << setting.env << "\n"
             << "      " << setting.help << "\n";
    }
    return text.str();
}

std::string describe(const ServerConfig& config) {
    std::ostringstream text;
    text << "bind=" << config.bind_address << " port=" << config.port
         << " admin_bind=" << config.admin_bind_address << " admin_port=" << config.admin_port
         << " workers=" << config.workers << " queue_length=" << config.queue_length
         << " io_threads=" << config.io_threads << " analysis_threads=" << config.analysis_threads
         << (config.cpu_budget.empty() ? "" : " ") << config.cpu_budget
         << " deadline_ms=" << config.deadline.count()
         << " read_deadline_ms=" << config.read_deadline.count()
         << " job_deadline_ms=" << config.job_deadline.count()
         << " job_retention_ms=" << config.job_retention.count()
         << " max_job_retention_ms=" << config.max_job_retention.count()
         << " max_jobs=" << config.max_jobs << " max_finished_jobs=" << config.max_finished_jobs
         << " max_event_streams=" << config.max_event_streams
         << " event_heartbeat_ms=" << config.event_heartbeat.count()
         << " job_workers=" << config.job_workers << " max_body_bytes=" << config.max_body_bytes
         << " max_batch_body_bytes=" << config.max_batch_body_bytes
         << " log_level=" << config.log_level << " instance=" << config.instance
         << " store=" << redacted_store(config.store) << " lease_ms=" << config.lease.count()
         << " chunk_points=" << config.chunk_points
         << " store_connections=" << config.store_connections
         << " store_deadline_ms=" << config.store_deadline.count()
         << " token=" << (config.token ? "set" : "unset")
         << " key_file=" << (config.key_file.empty() ? "unset" : config.key_file)
         << " webhook_allow=" << config.webhook_allow.size()
         << " webhook_secret=" << (config.webhook_secret ? "set" : "unset")
         << " webhook_backoff_ms=" << config.webhook_backoff.count()
         << " webhook_max_attempts=" << config.webhook_max_attempts
         << " webhook_timeout_ms=" << config.webhook_timeout.count()
         << " max_scenarios=" << config.max_scenarios << " allowed_hosts="
         << (config.allowed_hosts.empty() ? std::string("any") : join(config.allowed_hosts))
         << " allowed_origins="
         << (config.allowed_origins.empty() ? std::string("none") : join(config.allowed_origins));
    return text.str();
}

}  // namespace rollgap::service
