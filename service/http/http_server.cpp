#include "service/http/http_server.h"

#include "api/json_text.h"
#include "api/problem.h"
#include "api/text.h"
#include "service/analyses/table.h"
#include "service/http/admin_endpoints.h"
#include "service/http/job_endpoints.h"
#include "service/http/listener.h"
#include "service/http/request_checks.h"
#include "service/http/responses.h"
#include "service/http/routes.h"
#include "service/http/scenario_base.h"
#include "service/http/scenario_endpoints.h"
#include "service/http/service_state.h"
#include "service/http/sync_dispatch.h"
#include "service/http/webhook_deliverer.h"
#include "service/openapi.h"
#include "service/request_log.h"
#include "service/http/static_files.h"

#include <atomic>
#include <csignal>
#include <mutex>
#include <thread>
#include <utility>

#include <malloc.h>
#include <sys/socket.h>

#include <httplib.h>
#include <spdlog/spdlog.h>

namespace rollgap::service {
namespace {

using api::concat;
using nlohmann::json;
using namespace http;

// Threads of the admin listener: a probe or a scrape at a time, and one spare.
constexpr std::size_t admin_threads = 2;

// One request is handled start to end on one I/O thread: the context carries what the logger
// callback needs (it only sees the request and response).
struct RequestContext {
    bool active = false;
    SteadyClock::time_point start;
    std::string id;
    const Route* route = nullptr;
    std::size_t in_bytes = 0;
    std::string client = "anonymous";  // the client key's name (request_checks.h)
    std::string path;  // a POST or PUT's own path while httplib dispatches it (see pre_route)
};

// httplib dispatches POST and PUT by std::regex_match of the path against each registered
// pattern, and libstdc++'s regex executor recurses per character: a long path touched megabytes
// of a connection thread's stack. pre_route() has chosen the route already, so httplib is handed
// this one short path (its one registered pattern) and handle_post() puts the client's back.
constexpr std::string_view dispatched_path = "/rollgap-dispatch";
thread_local RequestContext t_context;

ListenerLimits limits_for(const ServerConfig& config) {
    ListenerLimits limits;
    limits.read_deadline = config.read_deadline;
    return limits;
}

}  // namespace

// ==============================================================================================

struct HttpServer::Impl {
    std::shared_ptr<spdlog::logger> request_logger;
    ServiceState state;
    SyncDispatch sync{state};
    JobRunner runner{state};
    WebhookDeliverer deliverer{state};
    JobEndpoints job_endpoints{state, runner};
    ScenarioEndpoints scenario_endpoints{state, store::StoredKind::stand};
    ScenarioEndpoints mill_endpoints{state, store::StoredKind::mill};
    Listener server{limits_for(state.config)};
    Listener admin{limits_for(state.config)};
    std::thread server_thread, admin_thread;
    int bound_port = -1;
    int admin_bound_port = -1;

    std::atomic<bool> started{false};
    // A body above --max-body-bytes (a large batch) is being parsed and checked (handle_post).
    std::atomic<bool> large_body_busy{false};
    std::atomic<bool> stopped{false};
    std::mutex shutdown_mutex;

    Impl(ServerConfig resolved, Evaluator evaluate, std::shared_ptr<spdlog::logger> logger)
        : request_logger(logger ? std::move(logger) : spdlog::default_logger()),
          state(std::move(resolved), std::move(evaluate)) {}

    const ServerConfig& config() const { return state.config; }

    // ---- request start and end -------------------------------------------------------------

    void begin(const httplib::Request& request, httplib::Response& response, bool on_admin) {
        RequestContext& context = t_context;
        if (!context.active) {
            context.active = true;
            context.start = SteadyClock::now();
            context.id = request_id_from(request.get_header_value("X-Request-Id"));
            context.route = match_route(request.path);
            // The admin listener serves the health and metrics routes only.
            if (on_admin && context.route != nullptr && !context.route->admin)
                context.route = nullptr;
            context.in_bytes = 0;
        }
        response.set_header("X-Request-Id", context.id);
        response.set_header("Accept-Ranges", "none");
        // JSON or CSV by the Accept header: caches keep one answer per Accept.
        if (context.route != nullptr && answers_csv(*context.route, request.method))
            response.set_header("Vary", "Accept");
        // While draining, clients are sent to reconnect (to another replica).
        if (state.draining) response.set_header("Connection", "close");
    }

    void end(const httplib::Request& request, const httplib::Response& response) {
        RequestContext& context = t_context;
        std::string id;
        double seconds = 0.0;
        std::string_view route = unmatched_route;
        if (context.active) {
            id = context.id;
            seconds = std::chrono::duration<double>(SteadyClock::now() - context.start).count();
            if (context.route != nullptr) route = context.route->pattern;
        } else {
            // Answered before routing (unparsable request line, refused headers).
            id = response.get_header_value("X-Request-Id");
        }
        state.metrics.observe_request(method_label(request.method), route, response.status,
                                      seconds);
        log_request(
            *request_logger,
            {id, method_label(request.method), route, request.path, response.status, seconds,
             context.active ? context.in_bytes : 0, response.body.size(), request.remote_addr,
             context.active ? std::string_view(context.client) : std::string_view("anonymous")});
        // A body or an answer above the ordinary limit (a batch, its 10,000-row result) built
        // documents tens of times its size: their freed memory goes back to the system now.
        const std::size_t in_bytes = context.active ? context.in_bytes : 0;
        if (std::max(in_bytes, response.body.size()) > state.config.max_body_bytes) malloc_trim(0);
        context = RequestContext{};
    }

    // ---- handlers ----------------------------------------------------------------------------

    httplib::Server::HandlerResponse pre_route(const httplib::Request& request,
                                               httplib::Response& response, bool on_admin) {
        begin(request, response, on_admin);
        if (refuse(t_context.route, request, response, config(), state.keys, on_admin,
                   t_context.client))
            return httplib::Server::HandlerResponse::Handled;
        if (request.method == "POST" || request.method == "PUT" || request.method == "PATCH") {
            auto& dispatched = const_cast<httplib::Request&>(request);
            t_context.path = std::exchange(dispatched.path, std::string(dispatched_path));
            return httplib::Server::HandlerResponse::Unhandled;  // → handle_post
        }
        guarded(response, [&] { handle_get_or_delete(*t_context.route, request, response); });
        return httplib::Server::HandlerResponse::Handled;
    }

    int expect_continue(const httplib::Request& request, httplib::Response& response,
                        bool on_admin) {
        begin(request, response, on_admin);
        if (refuse(t_context.route, request, response, config(), state.keys, on_admin,
                   t_context.client)) {
            response.set_header("Connection", "close");
            return response.status;
        }
        return 100;
    }

    // `handler` under the one exception guard (service::guarded): an exception is answered as
    // the problem `internal`.
    template <class Handler>
    static void guarded(httplib::Response& response, Handler&& handler) {
        const std::optional<Outcome> failed = service::guarded(
            [&]() -> std::optional<Outcome> {
                handler();
                return std::nullopt;
            },
            concat("request ", t_context.id));
        if (failed) set_json(response, failed->http_status, failed->body, failed->media_type());
    }

    void handle_get_or_delete(const Route& route, const httplib::Request& request,
                              httplib::Response& response) {
        switch (route.id) {
            case RouteId::scenario_calibrate:  // GET: the stored posterior
            case RouteId::scenarios:
            case RouteId::scenario:
            case RouteId::scenarios_default:  // served from code; DELETE: 422 (reserved)
                scenario_endpoints.get_or_delete(request, t_context.client, response);
                return;
            case RouteId::mills:
            case RouteId::mill:
            case RouteId::mills_default:
                mill_endpoints.get_or_delete(request, t_context.client, response);
                return;
            case RouteId::openapi:
                response.status = 200;
                response.set_content(openapi_text(), "application/json");
                return;
            case RouteId::livez:
            case RouteId::readyz:
            case RouteId::metrics: answer_admin(route.id, state, response); return;
            case RouteId::page:
            case RouteId::static_file:
                if (!serve_static_file(request, response)) {
                    set_problem(response, api::ProblemCode::not_found,
                                concat("no file ", api::quoted_for_message(request.path),
                                       " in the workbench"));
                }
                return;
            case RouteId::jobs: job_endpoints.list(request, response); return;
            case RouteId::job_events:
                job_endpoints.events(request.path.substr(jobs_prefix.size(),
                                                         request.path.size() - jobs_prefix.size() -
                                                             events_suffix.size()),
                                     response);
                return;
            case RouteId::job: {
                const std::string id = request.path.substr(jobs_prefix.size());
                if (request.method == "DELETE") {
                    job_endpoints.cancel(id, response);
                } else {
                    job_endpoints.get(request, id, response);
                }
                return;
            }
            default:
                // POST-only routes never get here (refuse() answered 405).
                set_problem(response, api::ProblemCode::internal, "no handler for this route");
                return;
        }
    }

    void handle_post(const httplib::Request& request, httplib::Response& response,
                     const httplib::ContentReader& read_content) {
        // pre_route() ran for this request on this thread and let it through.
        const_cast<httplib::Request&>(request).path = std::move(t_context.path);
        const Route* route = t_context.route;
        const std::size_t limit = body_limit(route, config());
        std::string body;
        bool too_large = false;
        const bool read = read_content([&](const char* data, std::size_t length) {
            if (body.size() + length > limit) {
                too_large = true;
                return false;
            }
            body.append(data, length);
            return true;
        });
        t_context.in_bytes = body.size();
        if (const Refusal refusal = current_refusal(); refusal != Refusal::none) {
            response.set_header("Connection", "close");
            set_problem(response, problem_for_refusal(refusal));
            return;
        }
        if (too_large || (!read && response.status == 413)) {
            response.set_header("Connection", "close");
            set_problem(response, api::ProblemCode::payload_too_large,
                        concat("the body exceeds the limit of ", std::to_string(limit), " bytes"));
            return;
        }
        if (!read) {
            response.set_header("Connection", "close");
            set_problem(response, api::ProblemCode::unreadable_input,
                        "the request body could not be read");
            return;
        }
        // A body above the 1 MiB of every other route (a batch's, up to
        // --max-batch-body-bytes) costs ~40 times its size while it is parsed and checked: one
        // such body at a time per replica, the next is told to come back.
        struct LargeBodySlot {
            std::atomic<bool>* busy = nullptr;
            ~LargeBodySlot() {
                if (busy != nullptr) busy->store(false);
            }
        } slot;
        if (body.size() > config().max_body_bytes) {
            if (large_body_busy.exchange(true)) {
                state.overloaded(response,
                                 "another large batch is being accepted; retry after Retry-After");
                return;
            }
            slot.busy = &large_body_busy;
        }
        guarded(response, [&] {
            json document = json::object();  // an empty body is the request {}
            if (!body.empty()) {
                auto parsed = api::parse_json_text(body);
                std::string().swap(body);  // parsed: the text is not needed any more
                if (auto* problem = std::get_if<api::Problem>(&parsed)) {
                    set_problem(response, *problem);
                    return;
                }
                document = std::move(std::get<json>(parsed));
            }
            if (route->id == RouteId::scenario_calibrate) {
                if (state.draining) {
                    state.overloaded(response,
                                     "the service is shutting down and accepts no new analyses");
                    return;
                }
                scenario_endpoints.calibrate(request, std::move(document), t_context.client,
                                             t_context.start, sync, response);
            } else if (route->id == RouteId::jobs) {
                job_endpoints.create(std::move(document),
                                     request.get_header_value("Idempotency-Key"), response);
            } else if (request.method == "PUT") {
                const bool mill = route->id == RouteId::mill || route->id == RouteId::mills_default;
                (mill ? mill_endpoints : scenario_endpoints)
                    .put(request, std::move(document), t_context.client, response);
            } else if (request.method == "PATCH") {
                const bool mill = route->id == RouteId::mill;
                (mill ? mill_endpoints : scenario_endpoints)
                    .patch(request, std::move(document), t_context.client, response);
            } else {
                run_route(*route, request, std::move(document), response);
            }
        });
    }

    // {"scenario", "options"} → the facade's {"analysis", "scenario", "options"}, prepared
    // here (a cheap 422 never waits for a worker), computed on a worker, answered as JSON or
    // CSV as `request` asks.
    void run_route(const Route& route, const httplib::Request& request, json body,
                   httplib::Response& response) {
        if (!body.is_object()) {
            set_problem(response, api::ProblemCode::invalid_request,
                        "the request body must be a JSON object",
                        {{"", concat("must be an object, not ", api::json_type_name(body)),
                          std::nullopt, std::nullopt}});
            return;
        }
        if (body.contains("analysis")) {
            set_problem(response, api::ProblemCode::invalid_request,
                        concat(route.pattern, " names its analysis itself"),
                        {{"/analysis",
                          concat("not a field of this endpoint: it runs '", route.analysis,
                                 "'; POST the full request to /v1/jobs to name the analysis"),
                          std::nullopt, std::nullopt}});
            return;
        }
        if (state.draining) {
            state.overloaded(response, "the service is shutting down and accepts no new analyses");
            return;
        }
        body["analysis"] = route.analysis;
        // Plant units in canonical keys before a stored base is merged under them.
        if (auto refused = canonicalise_units(body)) {
            set_outcome(request, *refused, response);
            return;
        }
        // A batch always runs as a job (202, its chunks spread over the replicas' workers).
        if (const Analysis* row = find_analysis(analyses(), route.analysis);
            row != nullptr && row->subject() == Subject::batch) {
            job_endpoints.create(std::move(body), request.get_header_value("Idempotency-Key"),
                                 response);
            return;
        }
        if (auto refused = resolve_base(body, state)) {
            answer_unresolved(state, *refused, response);
            return;
        }
        auto prepared = prepare(body);
        if (auto* problem = std::get_if<Outcome>(&prepared)) {
            set_outcome(request, *problem, response);
            return;
        }
        sync.run(request, std::move(body), std::move(std::get<PreparedRequest>(prepared)),
                 t_context.start, response);
    }

    // ---- lifecycle ---------------------------------------------------------------------------

    void configure(Listener& listener, std::size_t threads, bool on_admin) {
        // Connection threads of a bounded stack: what a request can touch and keep.
        listener.new_task_queue = [threads] {
            return new StackBoundedPool(threads, connection_stack_bytes);
        };
        // httplib's default sets SO_REUSEPORT, with which a second service binds a port in use
        // and the kernel spreads its connections over both (different job stores): keep
        // SO_REUSEADDR only (a restart may bind over connections in TIME_WAIT).
        listener.set_socket_options([](socket_t sock) {
            const int yes = 1;
            ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        });
        // The largest a route reads (a batch's); each route's own limit is checked as it reads.
        listener.set_payload_max_length(
            std::max(config().max_body_bytes, config().max_batch_body_bytes));
        // What the Keep-Alive header announces; the listener's own loop enforces them.
        listener.set_keep_alive_max_count(ListenerLimits{}.max_requests_per_connection);
        listener.set_keep_alive_timeout(
            std::chrono::duration_cast<std::chrono::seconds>(ListenerLimits{}.idle_timeout)
                .count());
        listener.set_tcp_nodelay(true);
        listener.set_pre_routing_handler(
            [this, on_admin](const httplib::Request& request, httplib::Response& response) {
                return pre_route(request, response, on_admin);
            });
        listener.set_expect_100_continue_handler(
            [this, on_admin](const httplib::Request& request, httplib::Response& response) {
                return expect_continue(request, response, on_admin);
            });
        if (!on_admin) {
            // pre_route() refused every POST or PUT its route does not take.
            const auto post_or_put = [this](const httplib::Request& request,
                                            httplib::Response& response,
                                            const httplib::ContentReader& reader) {
                handle_post(request, response, reader);
            };
            listener.Post(std::string(dispatched_path), post_or_put);
            listener.Put(std::string(dispatched_path), post_or_put);
            listener.Patch(std::string(dispatched_path), post_or_put);
        }
        listener.set_error_handler([](const httplib::Request&, httplib::Response& response) {
            if (const Refusal refusal = current_refusal(); refusal != Refusal::none) {
                set_problem(response, problem_for_refusal(refusal));
                response.set_header("Connection", "close");
            }
            if (!response.has_header("X-Request-Id"))
                response.set_header("X-Request-Id", new_request_id());
            if (!response.body.empty() || response.status == 204) return;
            set_problem(response, problem_for_status(response.status));
            // httplib's own 400: the request line or headers could not be parsed, so where the
            // next request would start cannot be trusted (found by fuzz_http_request: the bytes
            // after a malformed request line were read as requests, one 400 each). The
            // connection ends here, as nginx does.
            if (response.status == 400) response.set_header("Connection", "close");
        });
        listener.set_exception_handler(
            [](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
                guarded(response, [&] { std::rethrow_exception(error); });
            });
        listener.set_request_logger(
            [this](const httplib::Request& request, const httplib::Response& response) {
                end(request, response);
            });
        listener.set_refusal_renderer([](Refusal refusal, httplib::Response& response) {
            set_problem(response, problem_for_refusal(refusal));
            response.set_header("X-Request-Id", new_request_id());
        });
    }

    std::once_flag configured;
    void configure_once() {
        std::call_once(configured, [this] {
            configure(server, config().io_threads, false);
            configure(admin, admin_threads, true);
        });
    }

    static int bind(Listener& listener, const std::string& address, int port) {
        if (port == 0) return listener.bind_to_any_port(address);
        return listener.bind_to_port(address, port) ? port : -1;
    }

    bool start(std::string* error) {
        // A client that disconnects while we write must not kill the process.
        std::signal(SIGPIPE, SIG_IGN);
        if (auto refused = state.keys.load()) {
            if (error != nullptr) *error = *refused;
            return false;
        }
        configure_once();

        bound_port = bind(server, config().bind_address, config().port);
        if (bound_port > 0)
            admin_bound_port = bind(admin, config().admin_bind_address, config().admin_port);
        if (bound_port <= 0 || admin_bound_port <= 0) {
            if (error != nullptr) {
                const bool public_failed = bound_port <= 0;
                *error =
                    concat("cannot listen on ",
                           public_failed ? config().bind_address : config().admin_bind_address, ":",
                           std::to_string(public_failed ? config().port : config().admin_port),
                           public_failed ? "" : " (the admin port)",
                           ": the port is in use by another process or the address is not "
                           "available on this host");
            }
            return false;
        }
        if (!server.raise_backlog(SOMAXCONN))
            spdlog::warn("cannot raise the listen backlog; keeping httplib's");
        runner.start();
        deliverer.start();
        server_thread = std::thread([this] { server.listen_after_bind(); });
        admin_thread = std::thread([this] { admin.listen_after_bind(); });
        // httplib's stop() does nothing until listen_after_bind() has marked its server
        // running, so a shutdown right after start (a short test, an early SIGTERM) would leave
        // a thread blocked in accept() and the join in shutdown() waiting for ever.
        const auto until = SteadyClock::now() + std::chrono::seconds(5);
        while ((!server.is_running() || !admin.is_running()) && SteadyClock::now() < until) {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        started = true;
        return true;
    }

    void shutdown() {
        std::lock_guard lock(shutdown_mutex);
        if (stopped) return;
        state.draining = true;
        // Work this replica claimed and has not started goes back to the store at once.
        runner.stop_claiming();
        if (started) {
            const auto busy = [this] { return state.busy() || runner.held() > 0; };
            const auto patience = SteadyClock::now() + config().drain_timeout;
            while (busy() && SteadyClock::now() < patience) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
            if (busy()) {
                // Running job items stop and are given back (not failed): another replica
                // continues them.
                spdlog::warn("drain timeout ({} ms) passed with work in flight: cancelling it",
                             config().drain_timeout.count());
                state.hard_cancel = true;
                sync.stop_all();
            }
            server.stop_within(drain_close_grace);
            admin.stop_within(std::chrono::milliseconds(100));
            if (server_thread.joinable()) server_thread.join();
            if (admin_thread.joinable()) admin_thread.join();
        }
        runner.stop();
        deliverer.stop();
        state.pool.shutdown();
        stopped = true;
    }
};

// ==============================================================================================

HttpServer::HttpServer(ServerConfig config, Evaluator evaluator,
                       std::shared_ptr<spdlog::logger> request_logger)
    : impl_(std::make_unique<Impl>(config.resolved(), std::move(evaluator),
                                   std::move(request_logger))) {}

HttpServer::~HttpServer() { shutdown(); }

bool HttpServer::start(std::string* error) { return impl_->start(error); }
void HttpServer::serve_connection(int fd) {
    std::signal(SIGPIPE, SIG_IGN);
    impl_->configure_once();
    impl_->server.serve_connection(fd);
}
int HttpServer::port() const { return impl_->bound_port; }
int HttpServer::admin_port() const { return impl_->admin_bound_port; }
const ServerConfig& HttpServer::config() const { return impl_->state.config; }
void HttpServer::shutdown() { impl_->shutdown(); }
bool HttpServer::draining() const { return impl_->state.draining; }
bool HttpServer::running() const { return impl_->started && !impl_->stopped; }
const Metrics& HttpServer::metrics() const { return impl_->state.metrics; }
WorkerPoolStats HttpServer::pool_stats() const { return impl_->state.pool.stats(); }
store::JobCounts HttpServer::job_counts() {
    auto store = impl_->state.store.get();
    if (!store) return {};
    return store->counts().value.value_or(store::JobCounts{});
}
std::string HttpServer::metrics_text() { return http::metrics_text(impl_->state); }

}  // namespace rollgap::service
