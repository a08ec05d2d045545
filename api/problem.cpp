#include "api/problem.h"

#include <algorithm>
#include <array>
#include <stdexcept>

#include "api/text.h"

namespace rollgap::api {
namespace {

// 4xx: the client can fix the request; 5xx: the service could not serve a valid request.
// A well-formed JSON body with unprocessable content is 422 (RFC 9110 §15.5.21), syntax is 400.
constexpr std::array kinds{
    ProblemKind{ProblemCode::invalid_json, "invalid_json", 400, "Request body is not valid JSON"},
    ProblemKind{ProblemCode::invalid_request, "invalid_request", 422,
                "Request does not match the request schema"},
    ProblemKind{ProblemCode::invalid_scenario, "invalid_scenario", 422, "Scenario is invalid"},
    ProblemKind{ProblemCode::invalid_options, "invalid_options", 422,
                "Analysis options are invalid"},
    ProblemKind{ProblemCode::unknown_analysis, "unknown_analysis", 422, "Unknown analysis"},
    ProblemKind{ProblemCode::unreadable_input, "unreadable_input", 400,
                "Request could not be read"},
    ProblemKind{ProblemCode::unauthorized, "unauthorized", 401, "Unauthorized"},
    ProblemKind{ProblemCode::forbidden, "forbidden", 403, "Client key lacks the scope"},
    // 421 (RFC 9110 §15.5.20): this server does not answer for the authority the request
    // names; a rebound DNS name pointing a browser at a loopback service gets it.
    ProblemKind{ProblemCode::misdirected_request, "misdirected_request", 421,
                "Host is not served here"},
    ProblemKind{ProblemCode::cross_site_request, "cross_site_request", 403,
                "Cross-site request refused"},
    ProblemKind{ProblemCode::not_found, "not_found", 404, "Not found"},
    ProblemKind{ProblemCode::method_not_allowed, "method_not_allowed", 405, "Method not allowed"},
    ProblemKind{ProblemCode::payload_too_large, "payload_too_large", 413, "Request is too large"},
    ProblemKind{ProblemCode::unsupported_media_type, "unsupported_media_type", 415,
                "Unsupported media type"},
    ProblemKind{ProblemCode::request_timeout, "request_timeout", 408,
                "Request did not arrive in time"},
    ProblemKind{ProblemCode::uri_too_long, "uri_too_long", 414, "Request line is too long"},
    ProblemKind{ProblemCode::header_fields_too_large, "header_fields_too_large", 431,
                "Request header fields are too large"},
    ProblemKind{ProblemCode::invalid_header, "invalid_header", 400, "Request header is invalid"},
    ProblemKind{ProblemCode::not_acceptable, "not_acceptable", 406,
                "No representation in the format asked for"},
    ProblemKind{ProblemCode::conflict, "conflict", 409, "Request conflicts with stored state"},
    ProblemKind{ProblemCode::precondition_failed, "precondition_failed", 412,
                "Stored version has changed"},
    ProblemKind{ProblemCode::precondition_required, "precondition_required", 428,
                "If-Match is required"},
    ProblemKind{ProblemCode::overloaded, "overloaded", 503, "Service is overloaded"},
    // Synchronous analyses never need the store, so this is not `overloaded`: the service is
    // ready, only what is kept in the database waits for it.
    ProblemKind{ProblemCode::store_unavailable, "store_unavailable", 503,
                "Job store is unavailable"},
    // Not 503 like a full job store: jobs expire and free their slots, stored scenarios stay
    // until someone deletes them, so retrying would not help.
    ProblemKind{ProblemCode::insufficient_storage, "insufficient_storage", 507,
                "Stored scenario limit reached"},
    ProblemKind{ProblemCode::deadline_exceeded, "deadline_exceeded", 504,
                "Analysis exceeded its deadline"},
    // The facade cannot tell why its Control said stop: a caller whose reason is a deadline
    // reports deadline_exceeded (504) instead (service/evaluate.h). 409: the request was valid
    // but conflicts with the state of its job, which was cancelled.
    ProblemKind{ProblemCode::cancelled, "cancelled", 409, "Analysis was cancelled"},
    ProblemKind{ProblemCode::internal, "internal", 500, "Internal error"},
};

constexpr bool table_follows_enum_order() {
    for (std::size_t i = 0; i < kinds.size(); ++i) {
        if (static_cast<std::size_t>(kinds[i].code) != i) return false;
    }
    return true;
}
static_assert(table_follows_enum_order(), "problem table rows must follow the ProblemCode order");

}  // namespace

std::span<const ProblemKind> problem_kinds() { return kinds; }

const ProblemKind& problem_kind(ProblemCode code) {
    const auto index = static_cast<std::size_t>(code);
    if (index >= kinds.size()) throw std::out_of_range("problem code outside the table");
    return kinds[index];
}

std::optional<ProblemCode> problem_code_from_slug(std::string_view slug) {
    const auto row = std::find_if(kinds.begin(), kinds.end(),
                                  [slug](const ProblemKind& kind) { return kind.slug == slug; });
    if (row == kinds.end()) return std::nullopt;
    return row->code;
}

Problem make_problem(ProblemCode code, std::string detail, std::vector<FieldError> errors) {
    Problem problem;
    problem.code = code;
    problem.detail = std::move(detail);
    problem.errors = std::move(errors);
    return problem;
}

nlohmann::json problem_json(const Problem& problem) {
    const ProblemKind& kind = problem_kind(problem.code);
    nlohmann::json body = {
        {"type", concat(problem_type_base, kind.slug)},
        {"title", kind.title},
        {"status", kind.http_status},
        {"code", kind.slug},  // extension member: the slug without parsing the URI
        {"detail", problem.detail},
    };
    if (!problem.errors.empty()) {
        nlohmann::json errors = nlohmann::json::array();
        for (const FieldError& error : problem.errors) {
            nlohmann::json item = {{"pointer", error.pointer}, {"detail", error.detail}};
            if (error.bound) item["bound"] = *error.bound;
            if (error.unit) item["unit"] = *error.unit;
            errors.push_back(std::move(item));
        }
        body["errors"] = std::move(errors);
    }
    if (problem.errors_omitted > 0) body["errors_omitted"] = problem.errors_omitted;
    return body;
}

}  // namespace rollgap::api
