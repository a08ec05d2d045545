#include "service/http/request_checks.h"

#include <string>
#include <string_view>

#include "api/problem.h"
#include "api/field_errors.h"
#include "api/text.h"
#include "service/http/responses.h"

namespace rollgap::service::http {
namespace {

using api::concat;

bool authorized(const httplib::Request& request, const std::string& token) {
    const std::string header = request.get_header_value("Authorization");
    constexpr std::string_view scheme = "bearer ";
    if (header.size() < scheme.size() ||
        lower(std::string_view(header).substr(0, scheme.size())) != scheme) {
        return false;
    }
    return constant_time_equal(trim(std::string_view(header).substr(scheme.size())), token);
}

}  // namespace

bool refuse(const Route* route, const httplib::Request& request, httplib::Response& response,
            const ServerConfig& config) {
    bool refused = true;
    if (route == nullptr) {
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
    } else if (route->compute && config.token && !authorized(request, *config.token)) {
        response.set_header("WWW-Authenticate", "Bearer realm=\"rollgap\"");
        set_problem(response, api::ProblemCode::unauthorized,
                    "this endpoint needs the header Authorization: Bearer <token>");
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
               length && *length > config.max_body_bytes) {
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

}  // namespace rollgap::service::http
