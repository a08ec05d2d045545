#pragma once
// RFC 9457 problem details: every error the service can report is one row of one table
// (code, HTTP status, title), so the CLI, the HTTP server and the documentation cannot disagree.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace rollgap::api {

enum class ProblemCode {
    invalid_json,             // the body is not JSON (syntax, overflowing number, too deep)
    invalid_request,          // JSON, but the request envelope is wrong (unknown or mistyped field)
    invalid_scenario,         // the scenario violates the schema or a physical bound
    invalid_options,          // the analysis options violate their schema
    unknown_analysis,         // "analysis" names no analysis the service offers
    unreadable_input,         // the request could not be read at all (CLI: missing file)
    unauthorized,             // HTTP: a compute endpoint without the configured bearer token
    forbidden,                // HTTP: a known client key without the scope the route needs
    misdirected_request,      // HTTP: a Host this service does not answer for (DNS rebinding)
    cross_site_request,       // HTTP: an unsafe method from a foreign browser origin
    not_found,                // HTTP: no such route
    method_not_allowed,       // HTTP: route exists, method does not
    payload_too_large,        // the request exceeds the size limit
    unsupported_media_type,   // HTTP: not application/json
    request_timeout,          // HTTP: the request did not arrive within the read deadline
    uri_too_long,             // HTTP: the request line exceeds the limit
    header_fields_too_large,  // HTTP: the header section exceeds its size or field count limit
    invalid_header,           // HTTP: a header the server cannot take as sent (a NUL byte)
    not_acceptable,           // the result has no table in the format asked for (Accept: text/csv)
    conflict,                 // HTTP: the request conflicts with stored state (an Idempotency-Key
                              // reused with another body)
    precondition_failed,      // HTTP: If-Match names a version that is no longer current
    precondition_required,    // HTTP: overwriting a stored scenario needs If-Match
    overloaded,               // HTTP: every worker busy and the queue full
    store_unavailable,        // HTTP: the job store cannot be reached; retry later
    insufficient_storage,     // HTTP: the store holds as many stored scenarios as it may
    deadline_exceeded,        // the analysis did not finish within its time budget
    cancelled,                // the caller stopped the analysis (core::Control), e.g. a deleted job
    internal,                 // a bug: an exception escaped an analysis
};

struct ProblemKind {
    ProblemCode code;
    std::string_view slug;  // the last segment of the type URI, stable, snake_case
    int http_status;
    std::string_view title;  // short, the same for every occurrence (RFC 9457 §3.1.3)
};

// The table itself, in declaration order of ProblemCode.
std::span<const ProblemKind> problem_kinds();
const ProblemKind& problem_kind(ProblemCode code);
std::optional<ProblemCode> problem_code_from_slug(std::string_view slug);

inline constexpr std::string_view problem_media_type = "application/problem+json";
inline constexpr std::string_view problem_type_base = "https://rollgap.dev/problems/";

// One violation inside a request, located by an RFC 6901 JSON pointer into the request.
struct FieldError {
    std::string pointer;               // e.g. "/scenario/strip/reduction"
    std::string detail;                // for humans
    std::optional<std::string> bound;  // the allowed values, e.g. "(0, 0.7]" or "mixed | coulomb"
    std::optional<std::string> unit;   // the unit of the field and of the bound, e.g. "mm"
};

struct Problem {
    ProblemCode code = ProblemCode::internal;
    std::string detail;              // this occurrence, for humans
    std::vector<FieldError> errors;  // every violation found, not only the first
    std::size_t errors_omitted = 0;  // violations beyond the reporting cap

    int http_status() const { return problem_kind(code).http_status; }
};

Problem make_problem(ProblemCode code, std::string detail, std::vector<FieldError> errors = {});

// {"type", "title", "status", "detail", "errors": [{"pointer", "detail", "bound", "unit"}]}
nlohmann::json problem_json(const Problem& problem);

}  // namespace rollgap::api
