#pragma once
// The HTTP service: REST API v1 over cpp-httplib, in front of the same facade as the
// CLI (service::evaluate). See docs/http-api.md and service/openapi.json.
//
// Threads: httplib's I/O threads (config.io_threads) read requests and write answers; the
// model runs on the WorkerPool (config.workers) behind bounded queues. An I/O thread
// validates a request, queues it and waits for its computation until the request's deadline,
// then answers 504 and the computation is told to stop through core::Control. A second,
// admin listener with threads of its own serves /livez, /readyz and /metrics, so health
// answers whatever the public connections do. The parts live in service/http/.

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>
#include <spdlog/logger.h>

#include "core/control.h"
#include "service/config.h"
#include "service/evaluate.h"
#include "service/http/evaluator.h"
#include "service/store/job_store.h"
#include "service/metrics.h"
#include "service/worker_pool.h"

namespace rollgap::service {

// How long after the drain timeout connections may still take their answers.
inline constexpr std::chrono::milliseconds drain_close_grace{500};
// What shutdown() may take beyond the drain timeout: the close grace, then the workers
// returning from cancelled computations (they poll their Control between units of work).
inline constexpr std::chrono::milliseconds drain_margin{2000};

class HttpServer {
public:
    // `config` is resolved (config.resolved()) here. `request_logger` receives one line per
    // request (default: spdlog's default logger).
    explicit HttpServer(ServerConfig config, Evaluator evaluator = facade_evaluator(),
                        std::shared_ptr<spdlog::logger> request_logger = nullptr);
    ~HttpServer();  // shutdown()
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    // Binds (port 0: any free port) and serves on a background thread. On failure returns
    // false and says why in `error`.
    bool start(std::string* error = nullptr);
    int port() const;
    int admin_port() const;
    // Serves one connected socket on the calling thread, as the public listener serves an
    // accepted connection, and closes it; needs no start(). For the fuzz harness (a socketpair).
    void serve_connection(int fd);  // the admin listener's bound port
    const ServerConfig& config() const;

    // Graceful stop, idempotent and thread-safe: /readyz answers 503 and new synchronous
    // requests and jobs are refused (503); in-flight requests and jobs get up to
    // config.drain_timeout to finish, then are cancelled and every waiting request is answered
    // 503 at once; open connections get drain_close_grace to take their answers, then are shut
    // down; every thread is joined. Returns within drain_timeout + drain_margin.
    void shutdown();
    bool draining() const;
    bool running() const;  // started and not yet shut down

    // For tests and /metrics.
    const Metrics& metrics() const;
    WorkerPoolStats pool_stats() const;
    // Jobs by state in the store (all zero while it is unavailable).
    store::JobCounts job_counts();
    std::string metrics_text();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rollgap::service
