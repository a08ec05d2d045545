// RFC 9457 problem details: one table of error kinds, one document shape.

#include <doctest/doctest.h>

#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "api/problem.h"

using nlohmann::json;
using namespace rollgap::api;

TEST_CASE("the problem table has one row per code, unique slugs and error statuses") {
    std::set<std::string_view> slugs;
    for (const ProblemKind& kind : problem_kinds()) {
        CAPTURE(kind.slug);
        CHECK(slugs.insert(kind.slug).second);
        CHECK(kind.http_status >= 400);
        CHECK(kind.http_status < 600);
        CHECK_FALSE(kind.title.empty());
        CHECK(&problem_kind(kind.code) == &kind);
        CHECK(problem_code_from_slug(kind.slug) == kind.code);
    }
    CHECK_FALSE(problem_code_from_slug("no_such_problem").has_value());
}

TEST_CASE("the HTTP statuses of the problems") {
    CHECK(problem_kind(ProblemCode::invalid_json).http_status == 400);
    CHECK(problem_kind(ProblemCode::invalid_scenario).http_status == 422);
    CHECK(problem_kind(ProblemCode::unknown_analysis).http_status == 422);
    CHECK(problem_kind(ProblemCode::not_found).http_status == 404);
    CHECK(problem_kind(ProblemCode::method_not_allowed).http_status == 405);
    CHECK(problem_kind(ProblemCode::payload_too_large).http_status == 413);
    CHECK(problem_kind(ProblemCode::unsupported_media_type).http_status == 415);
    CHECK(problem_kind(ProblemCode::internal).http_status == 500);
    CHECK(problem_kind(ProblemCode::overloaded).http_status == 503);
    CHECK(problem_kind(ProblemCode::deadline_exceeded).http_status == 504);
}

TEST_CASE("a problem document has the RFC 9457 members and the field errors") {
    Problem problem =
        make_problem(ProblemCode::invalid_scenario, "2 violations",
                     {{"/scenario/strip/reduction", "0.8 is outside (0, 0.7]", "(0, 0.7]", "1"},
                      {"/scenario/strip/x", "unknown field 'x'", std::nullopt, std::nullopt}});
    const json body = problem_json(problem);
    CHECK(body["type"] == "https://rollgap.dev/problems/invalid_scenario");
    CHECK(body["title"] == "Scenario is invalid");
    CHECK(body["status"] == 422);
    CHECK(body["detail"] == "2 violations");
    REQUIRE(body["errors"].size() == 2);
    CHECK(body["errors"][0] == json{{"pointer", "/scenario/strip/reduction"},
                                    {"detail", "0.8 is outside (0, 0.7]"},
                                    {"bound", "(0, 0.7]"},
                                    {"unit", "1"}});
    CHECK_FALSE(body["errors"][1].contains("bound"));
    CHECK_FALSE(body.contains("errors_omitted"));
    CHECK(problem_json(make_problem(ProblemCode::internal, "x")).contains("errors") == false);
}
