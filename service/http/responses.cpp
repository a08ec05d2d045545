#include "service/http/responses.h"

#include <algorithm>
#include <cctype>
#include <charconv>

#include "api/field_errors.h"
#include "api/text.h"
#include "service/csv_answer.h"

namespace rollgap::service::http {

using api::ProblemCode;
using nlohmann::json;

std::string dump(const json& document) {
    // Echoed client strings are valid UTF-8 when parsed from text; replace, never throw.
    return document.dump(-1, ' ', false, json::error_handler_t::replace);
}

void set_json(httplib::Response& response, int status, const json& body,
              std::string_view media_type) {
    response.status = status;
    response.set_content(dump(body), std::string(media_type));
}

void set_problem(httplib::Response& response, const api::Problem& problem) {
    set_json(response, problem.http_status(), api::problem_json(problem), api::problem_media_type);
}

void set_outcome(const httplib::Request& request, const Outcome& outcome,
                 httplib::Response& response) {
    // units=plant: the table's speeds and viscosities in m/min and mPa·s (api/csv.h); the JSON
    // stays canonical. Checked on every answer, so a mistyped value is never silently SI.
    const std::string units = request.get_param_value("units");
    if (!parse_csv_units(units)) {
        invalid_parameter(response, "units",
                          "si or plant (plant: the CSV's speeds in m/min, "
                          "viscosities in mPa.s)");
        return;
    }
    if (outcome.ok() && wants_csv(request.get_header_value("Accept"))) {
        const CsvAnswer csv = csv_answer(outcome.body, request.get_param_value("table"), units);
        response.status = csv.status;
        response.set_content(csv.body, std::string(csv.media_type));
        return;
    }
    set_json(response, outcome.http_status, outcome.body, outcome.media_type());
}

void set_problem(httplib::Response& response, ProblemCode code, std::string detail,
                 std::vector<api::FieldError> errors) {
    set_problem(response, api::make_problem(code, std::move(detail), std::move(errors)));
}

api::Problem problem_for_status(int status) {
    switch (status) {
        case 400:
            return api::make_problem(ProblemCode::unreadable_input,
                                     "the HTTP request could not be parsed");
        case 404: return api::make_problem(ProblemCode::not_found, "no such route");
        case 413:
            return api::make_problem(ProblemCode::payload_too_large,
                                     "the request body exceeds the size limit");
        case 414:
            return api::make_problem(
                ProblemCode::uri_too_long,
                api::concat("the request line exceeds ",
                            std::to_string(default_max_request_line_bytes), " bytes"));
        default:
            return api::make_problem(
                ProblemCode::internal,
                api::concat("the request failed with HTTP status ", std::to_string(status)));
    }
}

api::Problem problem_for_refusal(Refusal refusal) {
    switch (refusal) {
        case Refusal::request_line_too_long:
            return api::make_problem(
                ProblemCode::uri_too_long,
                api::concat("the request line exceeds ",
                            std::to_string(default_max_request_line_bytes), " bytes"));
        case Refusal::header_too_large:
            return api::make_problem(
                ProblemCode::header_fields_too_large,
                api::concat("the request line and header fields exceed ",
                            std::to_string(default_max_header_bytes), " bytes"));
        case Refusal::too_many_header_fields:
            return api::make_problem(
                ProblemCode::header_fields_too_large,
                api::concat("the request has more than ", std::to_string(default_max_header_fields),
                            " header fields"));
        case Refusal::header_nul:
            return api::make_problem(ProblemCode::invalid_header, "a header contains a NUL byte");
        case Refusal::read_deadline:
            return api::make_problem(
                ProblemCode::request_timeout,
                "the request did not arrive within the read deadline; the connection closes");
        case Refusal::duplicate_content_length:
            return api::make_problem(
                ProblemCode::invalid_header,
                "Content-Length is given more than once; the connection closes");
        case Refusal::invalid_content_length:
            return api::make_problem(
                ProblemCode::invalid_header,
                "Content-Length is not a decimal number; the connection closes");
        case Refusal::unsupported_transfer_encoding:
            return api::make_problem(
                ProblemCode::invalid_header,
                "the only Transfer-Encoding accepted is exactly \"chunked\", once; the connection "
                "closes");
        case Refusal::transfer_encoding_with_content_length:
            return api::make_problem(
                ProblemCode::invalid_header,
                "Transfer-Encoding and Content-Length are both given; the connection closes");
        case Refusal::malformed_header_line:
            return api::make_problem(
                ProblemCode::invalid_header,
                "a header line is malformed (no colon, whitespace before it, a "
                "folded line or a bare LF); the connection closes");
        case Refusal::none: break;
    }
    return api::make_problem(ProblemCode::internal, "the request was refused for no known reason");
}

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

bool is_json_media_type(std::string_view content_type) {
    const std::string_view type = trim(content_type.substr(0, content_type.find(';')));
    return lower(type) == "application/json";
}

bool is_merge_patch_media_type(std::string_view content_type) {
    const std::string_view type = trim(content_type.substr(0, content_type.find(';')));
    return lower(type) == "application/merge-patch+json" || lower(type) == "application/json";
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

void invalid_parameter(httplib::Response& response, std::string_view name, std::string_view rule) {
    set_problem(response, api::ProblemCode::invalid_request,
                api::concat("query parameter '", name, "': ", rule),
                {api::FieldError{api::concat("/query/", name), api::concat("expected ", rule),
                                 std::string(rule), std::nullopt}});
}

bool read_page_limit(const httplib::Request& request, httplib::Response& response,
                     std::size_t max_page, std::size_t& limit) {
    if (!request.has_param("limit")) return true;
    const std::string text = request.get_param_value("limit");
    std::size_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc{} || end != text.data() + text.size() || value < 1 ||
        value > max_page) {
        invalid_parameter(response, "limit",
                          api::concat("an integer from 1 to ", std::to_string(max_page)));
        return false;
    }
    limit = value;
    return true;
}

}  // namespace rollgap::service::http
