#include "service/http/serve_main.h"

#include <malloc.h>

#include <algorithm>

#include "service/config.h"
#include "service/http/http_server.h"
#include "service/version.h"

#include <csignal>
#include <cstdlib>
#include <ostream>
#include <string>

#include <httplib.h>
#include <pthread.h>
#include <spdlog/spdlog.h>

namespace rollgap::service {
namespace {

constexpr int exit_ok = 0;
constexpr int exit_failure = 1;
constexpr int exit_usage = 2;
// The service could not start (a port in use, an address not on this host): like a usage
// error, something to fix in the settings or the environment, not an internal error.
constexpr int exit_start_failure = 2;

}  // namespace

int serve(const ServerConfig& parsed) {
    const ServerConfig config = parsed.resolved();
    // glibc gives each thread that allocates an arena of its own, up to 8 per core, and keeps
    // what a thread freed in its arena: a few large documents (a 10,000-row batch answered on
    // connection after connection) left ~1.7 GB resident on 2 cores, 250 MB with 2 arenas.
    // Two per worker keeps the compute threads from contending and the footprint bounded.
    mallopt(M_ARENA_MAX, static_cast<int>(std::max<std::size_t>(2, 2 * config.workers)));

    // One line per event, UTC, logfmt-style prefix; the request lines are logfmt throughout.
    spdlog::set_pattern("ts=%Y-%m-%dT%H:%M:%S.%eZ level=%l %v", spdlog::pattern_time_type::utc);
    spdlog::set_level(spdlog::level::from_str(config.log_level));
    spdlog::flush_on(spdlog::level::info);

    // Block the shutdown signals in every thread (the threads started below inherit the mask);
    // this thread waits for them with sigwait.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGINT);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    HttpServer server(config);
    std::string error;
    if (!server.start(&error)) {
        spdlog::critical("msg=\"{}\"", error);
        return exit_start_failure;
    }
    spdlog::info("msg=listening version={} address={}:{} admin_address={}:{} {}", version(),
                 config.bind_address, server.port(), config.admin_bind_address, server.admin_port(),
                 describe(config));

    int received = 0;
    while (sigwait(&signals, &received) != 0) {
    }
    spdlog::info("msg=draining signal={} drain_timeout_ms={}",
                 received == SIGTERM ? "SIGTERM" : "SIGINT", config.drain_timeout.count());
    server.shutdown();
    spdlog::info("msg=stopped");
    return exit_ok;
}

int healthcheck(const std::string& url, std::ostream& out, std::ostream& err) {
    constexpr std::string_view scheme = "http://";
    if (!std::string_view(url).starts_with(scheme)) {
        err << "rollgap healthcheck: only http:// URLs\n";
        return exit_usage;
    }
    const std::string rest = url.substr(scheme.size());
    const std::size_t slash = rest.find('/');
    const std::string host_port = rest.substr(0, slash);
    const std::string path = slash == std::string::npos ? "/" : rest.substr(slash);
    httplib::Client client("http://" + host_port);
    client.set_connection_timeout(2, 0);
    client.set_read_timeout(5, 0);
    const auto response = client.Get(path.c_str());
    if (!response) {
        err << "rollgap healthcheck: " << url << ": " << httplib::to_string(response.error())
            << '\n';
        return exit_failure;
    }
    out << url << ": " << response->status << '\n';
    return response->status == 200 ? exit_ok : exit_failure;
}

}  // namespace rollgap::service
