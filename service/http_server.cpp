#include "service/http_server.h"

#include "api/field_errors.h"
#include "api/json_text.h"
#include "api/name_suggestion.h"
#include "api/problem.h"
#include "api/request_json.h"
#include "api/scenario_json.h"
#include "api/text.h"
#include "service/analyses.h"
#include "service/openapi.h"
#include "service/request_log.h"
#include "service/static_files.h"
#include "service/version.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <fstream>
#include <mutex>
#include <optional>
#include <string_view>
#include <thread>
#include <vector>

#include <httplib.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

namespace rollgap::service {
namespace {

using api::concat;
using nlohmann::json;
using SteadyClock = std::chrono::steady_clock;

// ---- the facade, with the Control when it takes one ------------------------------------------

// service::evaluate(request, control) is being added next to evaluate(request); use it as soon
// as it exists, so cancellation reaches the computation without a change here.
template <class Request>
Outcome call_facade(const Request& request, const core::Control& control) {
    if constexpr (requires { service::evaluate(request, control); }) {
        return service::evaluate(request, control);
    } else {
        (void)control;
        return service::evaluate(request);
    }
}

// ---- routes ----------------------------------------------------------------------------------

enum Method : unsigned { get = 1, post = 2, del = 4 };

enum class RouteId {
    scenarios_default, roll_gap, stability, amplitude, tension_cycle, sweeps, evaluate,
    jobs, job, openapi, livez, readyz, metrics, page, static_file,
};

struct Route {
    RouteId id;
    std::string_view pattern;   // also the metrics label
    unsigned methods;
    bool compute;               // needs the bearer token when one is configured
    std::string_view analysis;  // the facade's analysis for the synchronous compute routes
};

constexpr std::array routes{
    Route{RouteId::scenarios_default, "/v1/scenarios/default", get, false, ""},
    Route{RouteId::roll_gap, "/v1/roll-gap", post, true, "roll_gap"},
    Route{RouteId::stability, "/v1/stability", post, true, "stability"},
    Route{RouteId::amplitude, "/v1/amplitude", post, true, "amplitude"},
    Route{RouteId::tension_cycle, "/v1/tension-cycle", post, true, "tension_cycle"},
    Route{RouteId::sweeps, "/v1/sweeps", post, true, "sweep"},
    Route{RouteId::evaluate, "/v1/evaluate", post, true, "evaluate"},
    Route{RouteId::jobs, "/v1/jobs", post, true, ""},
    Route{RouteId::job, "/v1/jobs/{id}", get | del, true, ""},
    Route{RouteId::openapi, "/openapi.json", get, false, ""},
    Route{RouteId::livez, "/livez", get, false, ""},
    Route{RouteId::readyz, "/readyz", get, false, ""},
    Route{RouteId::metrics, "/metrics", get, false, ""},
    // The browser workbench: the page at / and its files under /static/ (service/static_files.h).
    Route{RouteId::page, "/", get, false, ""},
    Route{RouteId::static_file, "/static/{file}", get, false, ""},
};

constexpr std::string_view unmatched_route = "unmatched";
constexpr std::string_view jobs_prefix = "/v1/jobs/";
constexpr std::string_view static_prefix = "/static/";

const Route* match_route(std::string_view path) {
    for (const Route& route : routes) {
        if (route.id == RouteId::static_file) {
            if (path.starts_with(static_prefix)) return &route;
        } else if (route.id == RouteId::job) {
            if (path.size() > jobs_prefix.size() && path.starts_with(jobs_prefix) &&
                path.find('/', jobs_prefix.size()) == std::string_view::npos) {
                return &route;
            }
        } else if (path == route.pattern) {
            return &route;
        }
    }
    return nullptr;
}

std::string allow_header(const Route& route) {
    std::string allow;
    const auto add = [&allow](std::string_view method) {
        if (!allow.empty()) allow += ", ";
        allow += method;
    };
    if (route.methods & get) {
        add("GET");
        add("HEAD");
    }
    if (route.methods & post) add("POST");
    if (route.methods & del) add("DELETE");
    add("OPTIONS");
    return allow;
}

bool method_allowed(const Route& route, std::string_view method) {
    if (method == "GET" || method == "HEAD") return (route.methods & get) != 0;
    if (method == "POST") return (route.methods & post) != 0;
    if (method == "DELETE") return (route.methods & del) != 0;
    return false;
}

// A closed set for the metrics label.
std::string_view method_label(std::string_view method) {
    static constexpr std::array<std::string_view, 9> known{"GET", "HEAD", "POST", "PUT", "DELETE",
                                                           "OPTIONS", "PATCH", "CONNECT", "TRACE"};
    const auto found = std::find(known.begin(), known.end(), method);
    return found == known.end() ? std::string_view("other") : *found;
}

std::string_view analysis_label(const json& request) {
    const auto name = request.find("analysis");
    if (name == request.end() || !name->is_string()) return "unknown";
    const Analysis* analysis = find_analysis(analyses(), name->get_ref<const std::string&>());
    return analysis == nullptr ? std::string_view("unknown") : analysis->name;
}

// ---- small HTTP helpers ----------------------------------------------------------------------

std::string lower(std::string_view text) {
    std::string result(text);
    for (char& c : result) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return result;
}

std::string_view trim(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
    return text;
}

// application/json, with or without parameters (charset=utf-8), any case.
bool is_json_media_type(std::string_view content_type) {
    const std::string_view type = trim(content_type.substr(0, content_type.find(';')));
    return lower(type) == "application/json";
}

bool has_body(const httplib::Request& request) {
    if (request.has_header("Transfer-Encoding")) return true;
    const std::string length = request.get_header_value("Content-Length");
    return !length.empty() && length != "0";
}

std::optional<std::size_t> content_length(const httplib::Request& request) {
    if (!request.has_header("Content-Length")) return std::nullopt;
    const std::string text = request.get_header_value("Content-Length");
    std::size_t value = 0;
    const auto parsed = std::from_chars(text.data(), text.data() + text.size(), value);
    if (parsed.ec != std::errc() || parsed.ptr != text.data() + text.size()) return std::nullopt;
    return value;
}

// Compares in time independent of where the strings differ.
bool constant_time_equal(std::string_view a, std::string_view b) {
    const std::size_t n = std::max(a.size(), b.size());
    unsigned difference = a.size() == b.size() ? 0u : 1u;
    for (std::size_t i = 0; i < n; ++i) {
        const auto x = static_cast<unsigned char>(i < a.size() ? a[i] : 0);
        const auto y = static_cast<unsigned char>(i < b.size() ? b[i] : 0);
        difference |= static_cast<unsigned>(x ^ y);
    }
    return difference == 0;
}

std::string dump(const json& document) {
    // Echoed client strings are valid UTF-8 when parsed from text; replace, never throw.
    return document.dump(-1, ' ', false, json::error_handler_t::replace);
}

void set_json(httplib::Response& response, int status, const json& body, std::string_view media_type) {
    response.status = status;
    response.set_content(dump(body), std::string(media_type));
}

void set_problem(httplib::Response& response, const api::Problem& problem) {
    set_json(response, problem.http_status(), api::problem_json(problem), api::problem_media_type);
}

void set_problem(httplib::Response& response, api::ProblemCode code, std::string detail,
                 std::vector<api::FieldError> errors = {}) {
    set_problem(response, api::make_problem(code, std::move(detail), std::move(errors)));
}

// Problem details for an HTTP status the api table has no row for (414, ...).
json http_problem(int status, std::string_view slug, std::string_view title, std::string_view detail) {
    json body = {
        {"type", slug.empty() ? std::string("about:blank") : concat(api::problem_type_base, slug)},
        {"title", title},
        {"status", status},
        {"detail", detail},
    };
    if (!slug.empty()) body["code"] = slug;
    return body;
}

// httplib produced this status itself (no handler ran, or the handler left the body empty).
json problem_for_status(int status) {
    switch (status) {
        case 400:
            return api::problem_json(
                api::make_problem(api::ProblemCode::unreadable_input, "the HTTP request could not be parsed"));
        case 404: return api::problem_json(api::make_problem(api::ProblemCode::not_found, "no such route"));
        case 413:
            return api::problem_json(
                api::make_problem(api::ProblemCode::payload_too_large, "the request body exceeds the size limit"));
        case 414: return http_problem(414, "", "URI Too Long", "the request line exceeds the limit");
        case 500:
            return api::problem_json(
                api::make_problem(api::ProblemCode::internal, "the request failed unexpectedly"));
        default:
            return http_problem(status, "", status >= 500 ? "Server Error" : "Client Error", "the request failed");
    }
}

// ---- per-request context on the I/O thread ---------------------------------------------------

// One request is handled start to end on one I/O thread: the context carries what the logger
// callback needs (it only sees the request and response).
struct RequestContext {
    bool active = false;
    SteadyClock::time_point start;
    std::string id;
    const Route* route = nullptr;
    std::size_t in_bytes = 0;
};
thread_local RequestContext t_context;

// ---- a synchronous computation handed to a worker --------------------------------------------

struct SyncCall {
    std::mutex mutex;
    std::condition_variable done;
    std::optional<Outcome> outcome;
    std::atomic<bool> abandoned{false};  // the I/O thread answered 504 and left
    SteadyClock::time_point deadline;
};

class InFlight {
public:
    explicit InFlight(std::atomic<int>& counter) : counter_(counter) { ++counter_; }
    ~InFlight() { --counter_; }
    InFlight(const InFlight&) = delete;
    InFlight& operator=(const InFlight&) = delete;

private:
    std::atomic<int>& counter_;
};

// httplib listens with a backlog of 5 (CPPHTTPLIB_LISTEN_BACKLOG, fixed in Debian's compiled
// library): a burst of new connections overflows it and the kernel drops SYNs, which clients
// retry only after a second. Calling listen() again on the bound socket raises the backlog.
class Server : public httplib::Server {
public:
    bool raise_backlog(int backlog) {
        const auto socket = svr_sock_.load();
        return socket != INVALID_SOCKET && ::listen(socket, backlog) == 0;
    }
};

std::optional<double> resident_memory_bytes() {
    std::ifstream statm("/proc/self/statm");
    long pages_total = 0, pages_resident = 0;
    if (!(statm >> pages_total >> pages_resident)) return std::nullopt;
    return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

}  // namespace

Evaluator facade_evaluator() {
    return [](const json& request, const core::Control& control) { return call_facade(request, control); };
}

// ==============================================================================================

struct HttpServer::Impl {
    ServerConfig config;
    Evaluator evaluator;
    std::shared_ptr<spdlog::logger> request_logger;

    Metrics metrics;
    WorkerPool pool;
    JobStore jobs;
    Server server;
    std::thread listener;
    int bound_port = -1;

    std::atomic<bool> started{false};
    std::atomic<bool> stopped{false};
    std::atomic<bool> draining{false};
    std::atomic<bool> hard_cancel{false};  // the drain timeout passed: stop everything
    std::atomic<int> in_flight{0};         // synchronous compute requests between read and answer
    std::mutex shutdown_mutex;

    const std::string default_scenario_text = dump(api::default_scenario_json());
    const std::chrono::system_clock::time_point start_time = std::chrono::system_clock::now();

    Impl(ServerConfig resolved, Evaluator evaluate, std::shared_ptr<spdlog::logger> logger)
        : config(std::move(resolved)),
          evaluator(evaluate ? std::move(evaluate) : facade_evaluator()),
          request_logger(logger ? std::move(logger) : spdlog::default_logger()),
          pool(config.workers, config.queue_length, 2 * config.max_jobs + 1, config.job_workers),
          jobs(config.max_jobs, config.job_retention, config.instance) {}

    // ---- request start and end -------------------------------------------------------------

    void begin(const httplib::Request& request, httplib::Response& response) {
        RequestContext& context = t_context;
        if (!context.active) {
            context.active = true;
            context.start = SteadyClock::now();
            context.id = request_id_from(request.get_header_value("X-Request-Id"));
            context.route = match_route(request.path);
            context.in_bytes = 0;
        }
        response.set_header("X-Request-Id", context.id);
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
            // httplib answered before routing (unparsable request line, URI too long).
            id = response.get_header_value("X-Request-Id");
        }
        metrics.observe_request(method_label(request.method), route, response.status, seconds);
        log_request(*request_logger, {id, method_label(request.method), route, request.path, response.status, seconds,
                                      context.active ? context.in_bytes : 0, response.body.size(),
                                      request.remote_addr});
        context = RequestContext{};
    }

    // ---- checks before the body is read ------------------------------------------------------

    // Fills `response` and returns true if the request is refused before its body is read.
    bool refuse(const httplib::Request& request, httplib::Response& response) {
        const Route* route = t_context.route;
        bool refused = true;
        if (route == nullptr) {
            set_problem(response, api::ProblemCode::not_found,
                        concat("no route ", api::quoted_for_message(request.path), "; GET /openapi.json lists them"));
        } else if (request.method == "OPTIONS") {
            response.status = 204;
            response.set_header("Allow", allow_header(*route));
        } else if (!method_allowed(*route, request.method)) {
            response.set_header("Allow", allow_header(*route));
            set_problem(response, api::ProblemCode::method_not_allowed,
                        concat(request.method, " is not allowed on ", route->pattern, "; allowed: ",
                               allow_header(*route)));
        } else if (route->compute && config.token && !authorized(request)) {
            response.set_header("WWW-Authenticate", "Bearer realm=\"rollgap\"");
            set_problem(response, api::ProblemCode::unauthorized,
                        "this endpoint needs the header Authorization: Bearer <token>");
        } else if (request.method == "POST" && !is_json_media_type(request.get_header_value("Content-Type"))) {
            const std::string sent = request.get_header_value("Content-Type");
            set_problem(response, api::ProblemCode::unsupported_media_type,
                        sent.empty() ? std::string("the body must be sent as Content-Type: application/json")
                                     : concat("the body must be application/json, not ", api::quoted_for_message(sent)));
        } else if (const auto length = content_length(request); length && *length > config.max_body_bytes) {
            set_problem(response, api::ProblemCode::payload_too_large,
                        concat("the body has ", std::to_string(*length), " bytes; the limit is ",
                               std::to_string(config.max_body_bytes)));
        } else {
            refused = false;
        }
        // The body was not read: the connection cannot carry another request.
        if (refused && has_body(request)) response.set_header("Connection", "close");
        return refused;
    }

    bool authorized(const httplib::Request& request) const {
        const std::string header = request.get_header_value("Authorization");
        constexpr std::string_view scheme = "bearer ";
        if (header.size() < scheme.size() || lower(std::string_view(header).substr(0, scheme.size())) != scheme) {
            return false;
        }
        return constant_time_equal(trim(std::string_view(header).substr(scheme.size())), *config.token);
    }

    // ---- handlers ----------------------------------------------------------------------------

    httplib::Server::HandlerResponse pre_route(const httplib::Request& request, httplib::Response& response) {
        begin(request, response);
        if (refuse(request, response)) return httplib::Server::HandlerResponse::Handled;
        if (request.method == "POST") return httplib::Server::HandlerResponse::Unhandled;  // → handle_post
        guarded(response, [&] { handle_get_or_delete(*t_context.route, request, response); });
        return httplib::Server::HandlerResponse::Handled;
    }

    int expect_continue(const httplib::Request& request, httplib::Response& response) {
        begin(request, response);
        if (refuse(request, response)) {
            response.set_header("Connection", "close");
            return response.status;
        }
        return 100;
    }

    template <class Handler>
    void guarded(httplib::Response& response, Handler&& handler) {
        try {
            handler();
        } catch (const std::exception& error) {
            spdlog::error("request {} failed: {}", t_context.id, error.what());
            set_problem(response, api::ProblemCode::internal, "the request failed unexpectedly; the log has the cause");
        } catch (...) {
            spdlog::error("request {} failed with a non-standard exception", t_context.id);
            set_problem(response, api::ProblemCode::internal, "the request failed unexpectedly; the log has the cause");
        }
    }

    void handle_get_or_delete(const Route& route, const httplib::Request& request, httplib::Response& response) {
        switch (route.id) {
            case RouteId::scenarios_default:
                response.status = 200;
                response.set_content(default_scenario_text, "application/json");
                return;
            case RouteId::openapi:
                response.status = 200;
                response.set_content(openapi_text(), "application/json");
                return;
            case RouteId::livez:
                set_json(response, 200, {{"status", "alive"}, {"instance", config.instance}, {"version", version()}},
                         "application/json");
                return;
            case RouteId::readyz:
                if (draining) {
                    response.set_header("Retry-After", std::to_string(config.retry_after.count()));
                    set_problem(response, api::ProblemCode::overloaded, "the service is shutting down");
                } else {
                    set_json(response, 200,
                             {{"status", "ready"}, {"instance", config.instance}, {"version", version()}},
                             "application/json");
                }
                return;
            case RouteId::metrics:
                response.status = 200;
                response.set_content(metrics_text(), "text/plain; version=0.0.4; charset=utf-8");
                return;
            case RouteId::page:
            case RouteId::static_file:
                if (!serve_static_file(request, response)) {
                    set_problem(response, api::ProblemCode::not_found,
                                concat("no file ", api::quoted_for_message(request.path), " in the workbench"));
                }
                return;
            case RouteId::job: {
                const std::string id = request.path.substr(jobs_prefix.size());
                if (request.method == "DELETE") {
                    cancel_job(id, response);
                } else if (auto document = jobs.document(id)) {
                    set_json(response, 200, *document, "application/json");
                } else {
                    job_not_found(id, response);
                }
                return;
            }
            default:
                // POST-only routes never get here (refuse() answered 405).
                set_problem(response, api::ProblemCode::internal, "no handler for this route");
                return;
        }
    }

    void job_not_found(const std::string& id, httplib::Response& response) {
        set_problem(response, api::ProblemCode::not_found,
                    concat("no job ", api::quoted_for_message(id),
                           " on this instance: it never existed, has expired or was deleted"));
    }

    void cancel_job(const std::string& id, httplib::Response& response) {
        json document;
        switch (jobs.cancel(id, &document)) {
            case CancelResult::not_found: job_not_found(id, response); return;
            case CancelResult::cancelled: set_json(response, 200, document, "application/json"); return;
            case CancelResult::cancel_requested: set_json(response, 202, document, "application/json"); return;
            case CancelResult::deleted: response.status = 204; return;
        }
    }

    void handle_post(const httplib::Request& /*request*/, httplib::Response& response,
                     const httplib::ContentReader& read_content) {
        // pre_route() ran for this request on this thread and let it through.
        const Route* route = t_context.route;
        std::string body;
        bool too_large = false;
        const bool read = read_content([&](const char* data, std::size_t length) {
            if (body.size() + length > config.max_body_bytes) {
                too_large = true;
                return false;
            }
            body.append(data, length);
            return true;
        });
        t_context.in_bytes = body.size();
        if (too_large || (!read && response.status == 413)) {
            response.set_header("Connection", "close");
            set_problem(response, api::ProblemCode::payload_too_large,
                        concat("the body exceeds the limit of ", std::to_string(config.max_body_bytes), " bytes"));
            return;
        }
        if (!read) {
            response.set_header("Connection", "close");
            set_problem(response, api::ProblemCode::unreadable_input, "the request body could not be read");
            return;
        }
        guarded(response, [&] {
            auto parsed = api::parse_json_text(body);
            if (auto* problem = std::get_if<api::Problem>(&parsed)) {
                set_problem(response, *problem);
                return;
            }
            json document = std::move(std::get<json>(parsed));
            if (route->id == RouteId::jobs) {
                create_job(std::move(document), response);
            } else {
                run_route(*route, std::move(document), response);
            }
        });
    }

    // {"scenario", "options"} → the facade's {"analysis", "scenario", "options"}.
    void run_route(const Route& route, json body, httplib::Response& response) {
        if (!body.is_object()) {
            set_problem(response, api::ProblemCode::invalid_request, "the request body must be a JSON object",
                        {{"", concat("must be an object, not ", api::json_type_name(body)), std::nullopt, std::nullopt}});
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
        body["analysis"] = route.analysis;
        run_sync(std::move(body), response);
    }

    void run_sync(json request, httplib::Response& response) {
        InFlight counted(in_flight);
        auto call = std::make_shared<SyncCall>();
        call->deadline = t_context.start + config.deadline;
        const bool queued = pool.try_submit(Lane::interactive, [this, call, request = std::move(request)] {
            if (call->abandoned || SteadyClock::now() >= call->deadline || hard_cancel) {
                metrics.count_skipped("deadline_exceeded");
                return;
            }
            core::Control control;
            control.threads = static_cast<int>(config.analysis_threads);
            control.cancelled = [this, call] {
                return call->abandoned.load(std::memory_order_relaxed) || SteadyClock::now() >= call->deadline ||
                       hard_cancel.load(std::memory_order_relaxed);
            };
            Outcome outcome = compute(request, control, [call] { return SteadyClock::now() >= call->deadline; },
                                      [] { return false; });
            {
                std::lock_guard lock(call->mutex);
                call->outcome = std::move(outcome);
            }
            call->done.notify_one();
        });
        if (!queued) {
            overloaded(response, concat("every worker is busy and ", std::to_string(config.queue_length),
                                        " requests are waiting; retry later"));
            return;
        }
        std::unique_lock lock(call->mutex);
        if (!call->done.wait_until(lock, call->deadline, [&] { return call->outcome.has_value(); })) {
            call->abandoned = true;
            set_problem(response, deadline_problem(config.deadline));
            return;
        }
        const Outcome& outcome = *call->outcome;
        if (outcome.problem == api::ProblemCode::cancelled) {
            // The facade cannot say why it was stopped (evaluate.h); here it is known.
            if (hard_cancel) {
                overloaded(response, "the service is shutting down; the analysis was stopped before it finished");
            } else {
                set_problem(response, deadline_problem(config.deadline));
            }
            return;
        }
        set_json(response, outcome.http_status, outcome.body, outcome.media_type());
    }

    static api::Problem deadline_problem(std::chrono::milliseconds budget) {
        return api::make_problem(api::ProblemCode::deadline_exceeded,
                                 concat("the analysis did not finish within ", std::to_string(budget.count()),
                                        " ms and was stopped; run it as a job (POST /v1/jobs) for a longer budget"));
    }

    void overloaded(httplib::Response& response, std::string detail) {
        response.set_header("Retry-After", std::to_string(config.retry_after.count()));
        set_problem(response, api::ProblemCode::overloaded, std::move(detail));
    }

    // Runs the evaluator on a worker and records the metrics. `late` and `cancelled_by_client`
    // say, after it returned, why it may have been stopped.
    template <class Late, class CancelledByClient>
    Outcome compute(const json& request, const core::Control& control, Late late,
                    CancelledByClient cancelled_by_client) {
        const std::string_view analysis = analysis_label(request);
        const auto start = SteadyClock::now();
        Outcome outcome;
        try {
            outcome = evaluator(request, control);
        } catch (const std::exception& error) {
            spdlog::error("analysis {} threw: {}", analysis, error.what());
            outcome = problem_outcome(api::make_problem(api::ProblemCode::internal,
                                                        "the analysis failed unexpectedly; the log has the cause"));
        } catch (...) {
            spdlog::error("analysis {} threw a non-standard exception", analysis);
            outcome = problem_outcome(api::make_problem(api::ProblemCode::internal,
                                                        "the analysis failed unexpectedly; the log has the cause"));
        }
        const double seconds = std::chrono::duration<double>(SteadyClock::now() - start).count();

        std::string_view label = "succeeded";
        if (cancelled_by_client()) {
            label = "cancelled";
        } else if (late() || hard_cancel) {
            label = "deadline_exceeded";
        } else if (outcome.ok()) {
            if (reports_solver_failure(outcome.body)) metrics.count_solver_failure(analysis, "solver_failure");
        } else if (outcome.problem == api::ProblemCode::deadline_exceeded) {
            label = "deadline_exceeded";
        } else if (outcome.problem == api::ProblemCode::cancelled) {
            label = "cancelled";
        } else if (outcome.http_status >= 500) {
            label = "failed";
            metrics.count_solver_failure(analysis, "internal");
        } else {
            label = "rejected";
        }
        metrics.observe_analysis(analysis, label, seconds);
        return outcome;
    }

    static bool reports_solver_failure(const json& body) {
        const auto result = body.find("result");
        if (result == body.end() || !result->is_object()) return false;
        const auto failed = [](const json& object) {
            const auto status = object.find("status");
            return status != object.end() && status->is_string() && *status == "solver_failure";
        };
        if (failed(*result)) return true;
        return std::any_of(result->begin(), result->end(),
                           [&](const json& member) { return member.is_object() && failed(member); });
    }

    // ---- jobs --------------------------------------------------------------------------------

    void create_job(json request, httplib::Response& response) {
        if (!request.is_object()) {
            set_problem(response, api::ProblemCode::invalid_request, "the request body must be a JSON object",
                        {{"", concat("must be an object, not ", api::json_type_name(request)), std::nullopt,
                          std::nullopt}});
            return;
        }
        if (api::nests_deeper_than(request, api::max_json_depth)) {
            set_problem(response, api::ProblemCode::invalid_request, "the request nests too deep");
            return;
        }
        api::FieldErrors errors;
        const api::AnalysisRequest envelope = api::analysis_request_from_json(request, errors);
        if (!errors.empty()) {
            set_problem(response, errors.to_problem(api::ProblemCode::invalid_request, "the request envelope is invalid"));
            return;
        }
        if (find_analysis(analyses(), envelope.analysis) == nullptr) {
            std::vector<std::string_view> names;
            for (const Analysis& row : analyses()) names.push_back(row.name);
            std::string detail = concat("unknown analysis ", api::quoted_for_message(envelope.analysis));
            if (const auto suggestion = api::closest_name(envelope.analysis, names)) {
                detail += concat("; did you mean '", *suggestion, "'?");
            }
            set_problem(response, api::ProblemCode::unknown_analysis,
                        concat("no analysis named ", api::quoted_for_message(envelope.analysis)),
                        {{"/analysis", std::move(detail), api::choices_text(names), std::nullopt}});
            return;
        }
        if (draining) {
            overloaded(response, "the service is shutting down and accepts no new jobs");
            return;
        }
        std::shared_ptr<Job> job =
            jobs.create(envelope.analysis, std::move(request), SteadyClock::now() + config.job_deadline);
        if (!job) {
            overloaded(response, concat("the job store is full (", std::to_string(jobs.capacity()),
                                        " jobs); retry later or DELETE finished jobs"));
            return;
        }
        if (!pool.try_submit(Lane::batch, [this, job] { run_job(job); })) {
            jobs.remove(job->id);
            overloaded(response, "the job queue is full; retry later");
            return;
        }
        response.set_header("Location", concat(jobs_prefix, job->id));
        if (auto document = jobs.document(job->id)) {
            set_json(response, 202, *document, "application/json");
        } else {
            response.status = 202;  // already finished and expired (retention 0)
        }
    }

    void run_job(const std::shared_ptr<Job>& job) {
        if (!jobs.start(job)) {
            metrics.count_skipped("cancelled");
            return;
        }
        const auto late = [job] { return SteadyClock::now() >= job->deadline; };
        const auto cancelled = [job] { return job->cancel_requested.load(); };
        core::Control control;
        control.threads = static_cast<int>(config.analysis_threads);
        control.cancelled = [this, late, cancelled] { return cancelled() || late() || hard_cancel.load(); };
        control.progress = [job](double fraction) {
            if (std::isfinite(fraction)) job->progress = std::clamp(fraction, 0.0, 1.0);
        };
        Outcome outcome = compute(job->request, control, late, cancelled);
        if (!cancelled() && (late() || hard_cancel)) outcome = problem_outcome(deadline_problem(config.job_deadline));
        jobs.finish(job, std::move(outcome));
    }

    // ---- metrics -----------------------------------------------------------------------------

    std::string metrics_text() {
        const WorkerPoolStats stats = pool.stats();
        const JobCounts counts = jobs.counts();
        std::vector<GaugeSample> gauges{
            {"rollgap_workers", "Compute worker threads.", "", static_cast<double>(stats.workers)},
            {"rollgap_workers_busy", "Compute workers running an analysis.", "", static_cast<double>(stats.busy)},
            {"rollgap_queue_depth", "Work waiting for a worker, by lane (interactive: synchronous requests, "
                                    "batch: jobs).",
             "lane=\"interactive\"", static_cast<double>(stats.interactive_queued)},
            {"rollgap_queue_depth", "", "lane=\"batch\"", static_cast<double>(stats.batch_queued)},
            {"rollgap_queue_capacity", "Work that may wait for a worker, by lane.", "lane=\"interactive\"",
             static_cast<double>(stats.interactive_capacity)},
            {"rollgap_queue_capacity", "", "lane=\"batch\"", static_cast<double>(stats.batch_capacity)},
            {"rollgap_requests_in_flight", "Synchronous compute requests read and not yet answered.", "",
             static_cast<double>(in_flight.load())},
            {"rollgap_jobs", "Stored jobs by state.", "state=\"queued\"", static_cast<double>(counts.queued)},
            {"rollgap_jobs", "", "state=\"running\"", static_cast<double>(counts.running)},
            {"rollgap_jobs", "", "state=\"succeeded\"", static_cast<double>(counts.succeeded)},
            {"rollgap_jobs", "", "state=\"failed\"", static_cast<double>(counts.failed)},
            {"rollgap_jobs", "", "state=\"cancelled\"", static_cast<double>(counts.cancelled)},
            {"rollgap_jobs_capacity", "Jobs the store holds at most.", "", static_cast<double>(jobs.capacity())},
            {"rollgap_ready", "1 while the service accepts work, 0 while it drains.", "", draining ? 0.0 : 1.0},
            {"process_start_time_seconds", "Start time of the process since the Unix epoch, seconds.", "",
             std::chrono::duration<double>(start_time.time_since_epoch()).count()},
        };
        if (const auto rss = resident_memory_bytes()) {
            gauges.push_back({"process_resident_memory_bytes", "Resident memory size, bytes.", "", *rss});
        }
        // HELP lines come from the first sample of each name.
        std::string previous_help;
        for (GaugeSample& gauge : gauges) {
            if (gauge.help.empty()) {
                gauge.help = previous_help;
            } else {
                previous_help = gauge.help;
            }
        }
        return metrics.render(gauges);
    }

    // ---- lifecycle ---------------------------------------------------------------------------

    bool start(std::string* error) {
        // A client that disconnects while we write must not kill the process.
        std::signal(SIGPIPE, SIG_IGN);

        const std::size_t io_threads = config.io_threads;
        server.new_task_queue = [io_threads] { return new httplib::ThreadPool(io_threads); };
        server.set_payload_max_length(config.max_body_bytes);
        // Keep connections open (clients reconnecting in bursts cost latency); idle ones close
        // after the keep-alive timeout.
        server.set_keep_alive_max_count(100000);
        server.set_keep_alive_timeout(5);
        server.set_read_timeout(10, 0);
        server.set_write_timeout(10, 0);
        server.set_tcp_nodelay(true);

        server.set_pre_routing_handler(
            [this](const httplib::Request& request, httplib::Response& response) { return pre_route(request, response); });
        server.set_expect_100_continue_handler(
            [this](const httplib::Request& request, httplib::Response& response) {
                return expect_continue(request, response);
            });
        for (const Route& route : routes) {
            if ((route.methods & post) == 0) continue;
            server.Post(std::string(route.pattern),
                        [this](const httplib::Request& request, httplib::Response& response,
                               const httplib::ContentReader& reader) { handle_post(request, response, reader); });
        }
        server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
            if (!response.body.empty() || response.status == 204) return;
            set_json(response, response.status, problem_for_status(response.status), api::problem_media_type);
            if (!response.has_header("X-Request-Id")) response.set_header("X-Request-Id", new_request_id());
        });
        server.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr) {
            set_problem(response, api::ProblemCode::internal, "the request failed unexpectedly");
        });
        server.set_logger(
            [this](const httplib::Request& request, const httplib::Response& response) { end(request, response); });

        if (config.port == 0) {
            bound_port = server.bind_to_any_port(config.bind_address);
        } else {
            bound_port = server.bind_to_port(config.bind_address, config.port) ? config.port : -1;
        }
        if (bound_port <= 0) {
            if (error != nullptr) {
                *error = concat("cannot listen on ", config.bind_address, ":", std::to_string(config.port),
                                " (address in use or not available)");
            }
            return false;
        }
        if (!server.raise_backlog(SOMAXCONN)) spdlog::warn("cannot raise the listen backlog; keeping httplib's");
        listener = std::thread([this] { server.listen_after_bind(); });
        started = true;
        return true;
    }

    bool busy() { return in_flight.load() > 0 || !pool.idle() || jobs.counts().active() > 0; }

    void shutdown() {
        std::lock_guard lock(shutdown_mutex);
        if (stopped) return;
        draining = true;
        if (started) {
            const auto patience = SteadyClock::now() + config.drain_timeout;
            while (busy() && SteadyClock::now() < patience) std::this_thread::sleep_for(std::chrono::milliseconds(5));
            if (busy()) {
                spdlog::warn("drain timeout ({} ms) passed with work in flight: cancelling it",
                             config.drain_timeout.count());
                hard_cancel = true;
                jobs.cancel_all();
                const auto grace = SteadyClock::now() + std::chrono::seconds(5);
                while (busy() && SteadyClock::now() < grace) std::this_thread::sleep_for(std::chrono::milliseconds(5));
            }
            server.stop();
            if (listener.joinable()) listener.join();
        }
        pool.shutdown();
        stopped = true;
    }
};

// ==============================================================================================

HttpServer::HttpServer(ServerConfig config, Evaluator evaluator, std::shared_ptr<spdlog::logger> request_logger)
    : impl_(std::make_unique<Impl>(config.resolved(), std::move(evaluator), std::move(request_logger))) {}

HttpServer::~HttpServer() { shutdown(); }

bool HttpServer::start(std::string* error) { return impl_->start(error); }
int HttpServer::port() const { return impl_->bound_port; }
const ServerConfig& HttpServer::config() const { return impl_->config; }
void HttpServer::shutdown() { impl_->shutdown(); }
bool HttpServer::draining() const { return impl_->draining; }
bool HttpServer::running() const { return impl_->started && !impl_->stopped; }
const Metrics& HttpServer::metrics() const { return impl_->metrics; }
WorkerPoolStats HttpServer::pool_stats() const { return impl_->pool.stats(); }
JobCounts HttpServer::job_counts() { return impl_->jobs.counts(); }
std::string HttpServer::metrics_text() { return impl_->metrics_text(); }

}  // namespace rollgap::service
