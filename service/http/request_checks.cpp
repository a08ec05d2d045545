#include "service/http/request_checks.h"

#include <algorithm>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "api/problem.h"
#include "api/field_errors.h"
#include "api/text.h"
#include "service/analyses/table.h"
#include "service/csv_answer.h"
#include "service/http/responses.h"

namespace rollgap::service::http {
namespace {

using api::concat;

// The value after "Bearer ", or nothing.
std::optional<std::string> bearer(const httplib::Request& request) {
    const std::string header = request.get_header_value("Authorization");
    constexpr std::string_view scheme = "bearer ";
    if (header.size() < scheme.size() ||
        lower(std::string_view(header).substr(0, scheme.size())) != scheme) {
        return std::nullopt;
    }
    return std::string(trim(std::string_view(header).substr(scheme.size())));
}

// The host of a Host header, lower case, without port and IPv6 brackets.
std::string host_of(std::string_view header) {
    std::string host;
    if (header.starts_with('[')) {
        const auto close = header.find(']');
        host = std::string(header.substr(1, close == std::string_view::npos ? close : close - 1));
    } else if (std::count(header.begin(), header.end(), ':') > 1) {
        host = std::string(header);  // a bare IPv6 address (a setting, never a Host header)
    } else {
        host = std::string(header.substr(0, header.find(':')));
    }
    return lower(host);
}

bool host_allowed(const httplib::Request& request, const ServerConfig& config) {
    // HTTP/1.0 without Host: a browser always sends one, so nothing to rebind.
    if (config.allowed_hosts.empty() || !request.has_header("Host")) return true;
    const std::string host = host_of(request.get_header_value("Host"));
    return std::any_of(
        config.allowed_hosts.begin(), config.allowed_hosts.end(),
        [&host](const std::string& allowed) { return allowed == "*" || host_of(allowed) == host; });
}

bool unsafe_method(const std::string& method) {
    return method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE";
}

// An unsafe request a browser sent from a page of another origin. The service's own origin
// (the workbench at /) is the one whose host and port are the Host the request was sent to;
// --allowed-origins adds others. Clients that are not browsers send neither header.
std::optional<std::string> cross_site(const httplib::Request& request, const ServerConfig& config) {
    if (!unsafe_method(request.method)) return std::nullopt;
    const std::string origin = lower(request.get_header_value("Origin"));
    if (!origin.empty() && std::find(config.allowed_origins.begin(), config.allowed_origins.end(),
                                     origin) != config.allowed_origins.end()) {
        return std::nullopt;
    }
    if (request.has_header("Origin")) {
        const std::string host = lower(request.get_header_value("Host"));
        const bool same = !host.empty() &&
                          (origin == concat("http://", host) || origin == concat("https://", host));
        if (!same) {
            return concat("the Origin ",
                          api::quoted_for_message(request.get_header_value("Origin")),
                          " is not this service's and not in --allowed-origins");
        }
    }
    const std::string site = lower(request.get_header_value("Sec-Fetch-Site"));
    if (site == "cross-site" || site == "same-site")
        return concat("Sec-Fetch-Site: ", site, ": a page of another site sent it");
    return std::nullopt;
}

// The route's media types the Accept header admits none of (q > 0), as a list for the 406;
// nothing when it admits one, or says nothing.
std::optional<std::string> refused_media(const Route& route, const httplib::Request& request) {
    const std::string accept = request.get_header_value("Accept");
    if (trim(accept).empty()) return std::nullopt;
    const std::vector<std::string_view> types = route_media_types(route, request.method);
    if (types.empty()) return std::nullopt;
    std::string offered;
    for (const std::string_view type : types) {
        if (accept_quality(accept, type) > 0.0) return std::nullopt;
        offered += concat(offered.empty() ? "" : " or ", type);
    }
    return offered;
}

// A header value listed once in Vary (merged into the Vary the answer already has).
void add_vary(httplib::Response& response, std::string_view token) {
    const auto found = response.headers.find("Vary");
    if (found == response.headers.end()) {
        response.set_header("Vary", std::string(token));
    } else if (found->second.find(token) == std::string::npos) {
        found->second = concat(found->second, ", ", token);
    }
}

// The headers a request from a browser page is allowed to send and to read (CORS).
constexpr std::string_view cors_request_headers =
    "Authorization, Content-Type, If-Match, If-None-Match, Idempotency-Key, X-Request-Id";
constexpr std::string_view cors_exposed_headers =
    "Location, ETag, Retry-After, X-Request-Id, Content-Disposition";

// CORS for the origins of --allowed-origins (none by default): the answer names the origin
// it may be read by and the headers the page may read; a preflight (OPTIONS with
// Access-Control-Request-Method) is told the route's methods and the request headers it may
// send. An origin not listed gets no CORS header: the browser keeps the answer from it.
void add_cors(const Route* route, const httplib::Request& request, httplib::Response& response,
              const ServerConfig& config) {
    if (config.allowed_origins.empty()) return;
    add_vary(response, "Origin");
    const std::string origin = lower(request.get_header_value("Origin"));
    if (origin.empty() || std::find(config.allowed_origins.begin(), config.allowed_origins.end(),
                                    origin) == config.allowed_origins.end())
        return;
    response.set_header("Access-Control-Allow-Origin", request.get_header_value("Origin"));
    response.set_header("Access-Control-Expose-Headers", std::string(cors_exposed_headers));
    if (request.method != "OPTIONS" || !request.has_header("Access-Control-Request-Method") ||
        route == nullptr)
        return;
    response.set_header("Access-Control-Allow-Methods", allow_header(*route));
    response.set_header("Access-Control-Allow-Headers", std::string(cors_request_headers));
    response.set_header("Access-Control-Max-Age", "600");
}

}  // namespace

Scope route_scope(const Route& route, std::string_view method) {
    const bool reads = method == "GET" || method == "HEAD";
    switch (route.id) {
        case RouteId::scenarios:
        case RouteId::scenario:
        case RouteId::mills:
        case RouteId::mill:
        case RouteId::scenario_calibrate: return reads ? scope_read : scope_write;
        case RouteId::jobs:
        case RouteId::job:
        case RouteId::job_events: return reads ? scope_read : scope_compute;
        default: return scope_compute;
    }
}

std::size_t body_limit(const Route* route, const ServerConfig& config) {
    if (route != nullptr && route->id == RouteId::analysis) {
        const Analysis* analysis = find_analysis(analyses(), route->analysis);
        if (analysis != nullptr && analysis->subject() == Subject::batch)
            return config.max_batch_body_bytes;
    }
    return config.max_body_bytes;
}

bool refuse(const Route* route, const httplib::Request& request, httplib::Response& response,
            const ServerConfig& config, KeyRing& keys, bool on_admin, std::string& client) {
    bool refused = true;
    client = "anonymous";
    if (!on_admin) add_cors(route, request, response, config);
    std::optional<ClientIdentity> identity;
    const bool needs_key = route != nullptr && route->compute && keys.enabled() &&
                           request.method != "OPTIONS" && method_allowed(*route, request.method);
    if (needs_key) {
        if (const auto value = bearer(request)) identity = keys.identify(*value);
        if (identity) client = identity->name;
    }
    std::optional<std::string> foreign;
    if (!on_admin && !host_allowed(request, config)) {
        // Never echo the Host: it is what a rebinding page chose.
        set_problem(response, api::ProblemCode::misdirected_request,
                    "this service does not answer for the Host of the request; the names it "
                    "serves are set with --allowed-hosts");
    } else if (route == nullptr) {
        set_problem(response, api::ProblemCode::not_found,
                    concat("no route ", api::quoted_for_message(request.path),
                           "; GET /openapi.json lists them"));
    } else if (request.method == "OPTIONS") {
        response.status = 204;
        response.set_header("Allow", allow_header(*route));
    } else if (!method_allowed(*route, request.method)) {
        response.set_header("Allow", allow_header(*route));
        set_problem(response, api::ProblemCode::method_not_allowed,
                    concat(request.method, " is not allowed on ", route->pattern,
                           "; allowed: ", allow_header(*route)));
    } else if (foreign = on_admin ? std::nullopt : cross_site(request, config); foreign) {
        set_problem(response, api::ProblemCode::cross_site_request,
                    concat(request.method,
                           " from a browser page of another origin is refused: ", *foreign));
    } else if (needs_key && !identity) {
        response.set_header("WWW-Authenticate", "Bearer realm=\"rollgap\"");
        set_problem(response, api::ProblemCode::unauthorized,
                    "this endpoint needs the header Authorization: Bearer <token> with a known "
                    "token or client key");
    } else if (const Scope scope = route_scope(*route, request.method);
               needs_key && !identity->has(scope)) {
        response.set_header(
            "WWW-Authenticate",
            concat("Bearer realm=\"rollgap\", error=\"insufficient_scope\", scope=\"",
                   scope_name(scope), "\""));
        set_problem(
            response, api::ProblemCode::forbidden,
            concat("the client key ", identity->name, " lacks the scope ", scope_name(scope),
                   " that ", request.method, " ", route->pattern, " needs"));
    } else if (const auto offered = refused_media(*route, request); offered) {
        set_problem(response, api::ProblemCode::not_acceptable,
                    concat("the Accept header ",
                           api::quoted_for_message(request.get_header_value("Accept")),
                           " admits none of what ", request.method, " ", route->pattern,
                           " answers with: ", *offered));
    } else if (request.method == "PATCH" && has_body(request) &&
               !is_merge_patch_media_type(request.get_header_value("Content-Type"))) {
        // RFC 7396: a merge patch says so (application/json is taken as one too).
        set_problem(response, api::ProblemCode::unsupported_media_type,
                    concat("a PATCH body is a JSON merge patch: Content-Type: "
                           "application/merge-patch+json, not ",
                           api::quoted_for_message(request.get_header_value("Content-Type"))));
    } else if ((request.method == "POST" || request.method == "PUT") && has_body(request) &&
               !is_json_media_type(request.get_header_value("Content-Type"))) {
        // An empty body is the request {} whatever its declared type.
        const std::string sent = request.get_header_value("Content-Type");
        set_problem(
            response, api::ProblemCode::unsupported_media_type,
            sent.empty()
                ? std::string("the body must be sent as Content-Type: application/json")
                : concat("the body must be application/json, not ", api::quoted_for_message(sent)));
    } else if (const auto length = content_length(request);
               length && *length > body_limit(route, config)) {
        set_problem(response, api::ProblemCode::payload_too_large,
                    concat("the body has ", std::to_string(*length), " bytes; the limit is ",
                           std::to_string(body_limit(route, config))));
    } else {
        refused = false;
    }
    // The body was not read: the connection cannot carry another request.
    if (refused && has_body(request)) response.set_header("Connection", "close");
    return refused;
}

}  // namespace rollgap::service::http
