#pragma once
// Configuration of the HTTP service (`rollgap serve`): every setting is a flag and an
// environment variable; a flag wins over the variable, the variable over the default.
// The table of settings (config_settings()) is what CLI11 parses, what --help prints and what
// docs/operations.md ("Configuration") documents.

#include <chrono>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include <vector>

#include "service/store/dsn_redaction.h"
#include "service/webhooks.h"

namespace CLI {  // NOLINT(readability-identifier-naming): CLI11's namespace
class App;
}

namespace rollgap::service {

struct ServerConfig {
    std::string bind_address = "127.0.0.1";        // the container image sets ROLLGAP_BIND=0.0.0.0
    int port = 8080;                               // 0: any free port (tests)
    std::string admin_bind_address = "127.0.0.1";  // /livez, /readyz, /metrics on their own threads
    int admin_port = 8081;                         // 0: any free port (tests)
    bool admin_port_set = false;    // given by flag or environment; else --port 0 makes it 0 too
    std::size_t workers = 0;        // the compute pool's threads; 0: the CPUs the process may use
    std::size_t queue_length = 64;  // synchronous requests waiting for a worker
    std::size_t io_threads = 128;   // HTTP connection threads (one per open connection);
                                    // above workers + queue_length, so overload is a fast 503
    std::size_t analysis_threads = 0;  // workers one analysis may spread over; 0: all of them
    std::string cpu_budget;            // resolved: how the CPUs were counted (describe(CpuBudget))
    std::chrono::milliseconds deadline{30'000};  // synchronous requests, from arrival
    std::chrono::milliseconds read_deadline{
        10'000};  // a request's headers and body, from its first byte
    std::chrono::milliseconds job_deadline{600'000};   // asynchronous jobs, from creation
    std::chrono::milliseconds job_retention{600'000};  // finished jobs are kept this long
    // The longest retention a job may ask for (its retention_s).
    std::chrono::milliseconds max_job_retention{86'400'000};
    std::size_t max_jobs = 256;            // jobs queued or running at once
    std::size_t max_finished_jobs = 1000;  // finished jobs kept; the oldest go first
    // Server-sent event streams of jobs open at once (each holds a connection thread), and the
    // longest silence on one: a comment line keeps proxies and clients from timing it out.
    std::size_t max_event_streams = 32;
    std::chrono::milliseconds event_heartbeat{10'000};
    std::size_t job_workers = 0;          // workers jobs may occupy at once; 0: max(1, workers/2)
    std::chrono::seconds retry_after{1};  // the Retry-After of 503 answers
    std::chrono::milliseconds drain_timeout{25'000};  // SIGTERM: how long in-flight work may take
    std::size_t max_body_bytes = 1024 * 1024;
    // POST /v1/batches: up to 10,000 items of ~1 kB each (docs/http-api.md, "Batches").
    std::size_t max_batch_body_bytes = 8 * 1024 * 1024;
    std::chrono::milliseconds batch_deadline{3'600'000};  // a batch job, from creation
    std::string log_level = "info";    // trace debug info warn error critical off
    std::optional<std::string> token;  // bearer token for the compute endpoints; never logged
                                       // (a client key named "token" with every scope)
    std::string key_file;  // client keys with scopes (service/http/client_keys.h), re-read
                           // when it changes; empty: none
    // Host names (without port) the public listener answers for; empty: when bound to
    // loopback, the bind address, localhost, 127.0.0.1 and ::1 (resolved()), otherwise any.
    // "*": any (a front proxy in the same pod decides which names are served).
    std::vector<std::string> allowed_hosts;
    // Browser origins (scheme://host[:port]) whose unsafe requests are accepted besides the
    // service's own origin.
    std::vector<std::string> allowed_origins;
    // Completion callbacks (docs/http-api.md): the URL prefixes a job's callback_url may name
    // (none: callbacks refused), the HMAC secret that signs them (from a file, like the DSN;
    // never logged), the wait after the first failed attempt (doubling, at most 5 min) and
    // the attempts made before a delivery is given up.
    std::vector<WebhookUrl> webhook_allow;
    std::optional<std::string> webhook_secret;
    std::chrono::milliseconds webhook_backoff{1000};
    std::size_t webhook_max_attempts = 10;
    // An attempt as a whole, connect to the answer's last byte (a receiver that dribbles passes
    // every per-read timeout); below the deliverer's lease, so no other replica claims it
    // meanwhile.
    std::chrono::milliseconds webhook_timeout{15'000};
    std::size_t max_scenarios = 1000;  // stored scenarios (names), beyond: 507
    std::string instance;              // names this replica in job documents; default: host name
    // The job store (docs/job-store.md). `store` empty: sqlite:<data_dir>/jobs.db, so one
    // machine keeps its jobs across restarts with no server to run.
    std::string data_dir = "rollgap-data";  // relative to the working directory
    std::string store;                      // sqlite:PATH | postgresql://… | postgresql-file:PATH
    std::chrono::milliseconds lease{15'000};  // a claimed work item's lease, renewed at a third
    std::size_t chunk_points = 25;            // sweep points / map cells per work item
    std::size_t store_connections = 4;        // store threads = PostgreSQL connections of a replica
    std::chrono::milliseconds store_deadline{2000};  // one store operation, then 503

    // Resolved values (workers = the CPU budget, analysis_threads = workers, job_workers = ...);
    // call after parsing.
    ServerConfig resolved() const;
};

struct ConfigSetting {
    std::string_view flag;   // "--port"
    std::string_view env;    // "ROLLGAP_PORT"
    std::string_view value;  // "N", "ADDRESS", "MS", ...
    std::string_view help;   // one line, with the default
};
std::span<const ConfigSetting> config_settings();

struct ConfigHelp {};  // --help was asked for

// The table's flags on a CLI11 command (`rollgap serve`), each with its environment variable as
// fallback (a flag wins) and stored into `config` as it is parsed; a value the table refuses
// throws CLI::ValidationError with the table's message. `config` must outlive the parse.
void add_server_options(CLI::App& command, ServerConfig& config);
// After a successful parse: refuses unknown options (naming no value) and applies the token's own
// rule (ROLLGAP_TOKEN, environment only; a token file wins). An error is a message for stderr.
std::optional<std::string> finish_server_config(const CLI::App& command, ServerConfig& config);

// Parses `arguments` (after "serve") over the process environment: the two steps above.
std::variant<ServerConfig, ConfigHelp, std::string> parse_server_config(
    std::span<const std::string_view> arguments);

std::string config_usage();

// "bind=127.0.0.1 port=8080 workers=2 ... token=set": for the start-up log line, no secret.
std::string describe(const ServerConfig& config);

// The store setting for logs and libpq texts without secrets (service/store/dsn_redaction.h).
using store::redact_dsn_secrets;
using store::redacted_store;

}  // namespace rollgap::service
