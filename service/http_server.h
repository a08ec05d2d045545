#pragma once
// The HTTP service: REST API v1 over cpp-httplib, in front of the same facade as the
// CLI (service::evaluate). See the README's "HTTP service" and service/openapi.json.
//
// Threads: httplib's I/O threads (config.io_threads) read requests and write answers; the
// model runs on the WorkerPool (config.workers) behind bounded queues. An I/O thread waits
// for its computation until the request's deadline, then answers 504 and the computation is
// told to stop through core::Control.

#include <functional>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>
#include <spdlog/logger.h>

#include "core/control.h"
#include "service/config.h"
#include "service/evaluate.h"
#include "service/jobs.h"
#include "service/metrics.h"
#include "service/worker_pool.h"

namespace rollgap::service {

// What computes an outcome. The default is the facade; tests inject slow or blocking ones.
using Evaluator = std::function<Outcome(const nlohmann::json& request, const core::Control& control)>;
Evaluator facade_evaluator();

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
    const ServerConfig& config() const;

    // Graceful stop, idempotent and thread-safe: /readyz answers 503 and new jobs are refused;
    // in-flight requests and jobs get up to config.drain_timeout to finish, then are cancelled;
    // then the listening socket closes and every thread is joined.
    void shutdown();
    bool draining() const;
    bool running() const;  // started and not yet shut down

    // For tests and /metrics.
    const Metrics& metrics() const;
    WorkerPoolStats pool_stats() const;
    JobCounts job_counts();
    std::string metrics_text();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rollgap::service
