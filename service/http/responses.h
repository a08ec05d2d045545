#pragma once
// Writing answers: JSON documents and RFC 9457 problems (every error body is a row of
// api/problem.h's table, also those httplib or the connection layer produce), and the small
// header helpers the request checks share.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/problem.h"
#include "service/evaluate.h"
#include "service/http/listener.h"

namespace rollgap::service::http {

std::string dump(const nlohmann::json& document);

void set_json(httplib::Response& response, int status, const nlohmann::json& body,
              std::string_view media_type);
void set_problem(httplib::Response& response, const api::Problem& problem);
// An outcome as `request` asks for it, chosen before anything is serialised: a success as its
// CSV table when the Accept header prefers text/csv (the `table` parameter picks one; 406 when
// there is none, service/csv_answer.h), otherwise the JSON body (a problem always as JSON).
// The body is an analysis's answer or a job document.
void set_outcome(const httplib::Request& request, const Outcome& outcome,
                 httplib::Response& response);
void set_problem(httplib::Response& response, api::ProblemCode code, std::string detail,
                 std::vector<api::FieldError> errors = {});

// The problem of a status httplib produced itself (no handler ran, or it left the body empty).
api::Problem problem_for_status(int status);

// The problem of a request the connection layer stopped reading.
api::Problem problem_for_refusal(Refusal refusal);

std::string lower(std::string_view text);
std::string_view trim(std::string_view text);
// application/json, with or without parameters (charset=utf-8), any case.
bool is_json_media_type(std::string_view content_type);
// application/merge-patch+json (RFC 7396), or application/json.
bool is_merge_patch_media_type(std::string_view content_type);
// The request announces a body (chunked, or a non-zero Content-Length).
bool has_body(const httplib::Request& request);

// A refused query parameter is a field error like any other: 422 at `/query/<name>`, its rule
// as the bound.
void invalid_parameter(httplib::Response& response, std::string_view name, std::string_view rule);
// The `limit` of a paged listing (GET /v1/jobs, GET /v1/scenarios), an integer from 1 to
// `max_page`; `limit` keeps its value when the parameter is absent. False (and the 422 in
// `response`) when it is refused.
bool read_page_limit(const httplib::Request& request, httplib::Response& response,
                     std::size_t max_page, std::size_t& limit);
std::optional<std::size_t> content_length(const httplib::Request& request);
// Compares in time independent of where the strings differ.
bool constant_time_equal(std::string_view a, std::string_view b);

}  // namespace rollgap::service::http
