// The facade (service::evaluate) and the command line on top of it: the same request gives
// the same outcome whichever way it arrives, and nothing escapes as an exception.

#include <doctest/doctest.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "api/scenario_json.h"
#include "service/cli.h"
#include "service/evaluate.h"
#include "service/http/serve_main.h"
#include "service/version.h"

using nlohmann::json;
using namespace rollgap;
using namespace rollgap::service;

namespace {

const json default_request = {{"analysis", "roll_gap"}};

struct CliRun {
    int exit_status;
    std::string out;
    std::string err;
};

CliRun run(std::vector<std::string_view> arguments, const std::string& input = "") {
    std::istringstream in(input);
    std::ostringstream out, err;
    // As the executable does (cli_main.cpp): the HTTP layer's commands handed in.
    const int status = run_cli(arguments, in, out, err, {serve, healthcheck});
    return {status, out.str(), err.str()};
}

}  // namespace

TEST_CASE("the default roll_gap request solves the default scenario") {
    const Outcome outcome = evaluate(default_request);
    REQUIRE(outcome.ok());
    CHECK(outcome.http_status == 200);
    CHECK(outcome.media_type() == "application/json");
    CHECK(outcome.body["analysis"] == "roll_gap");
    CHECK(outcome.body["scenario"] == api::default_scenario_json());
    CHECK(outcome.body["options"] == json{{"distributions", true}});
    const json& result = outcome.body["result"];
    CHECK(result["status"] == "ok");
    CHECK(result["force_kN"].get<double>() > 0.0);
    // The neutral point lies inside the bite.
    CHECK(result["neutral_point_mm"].get<double>() > 0.0);
    CHECK(result["neutral_point_mm"].get<double>() < result["contact_length_mm"].get<double>());
    const json& distribution = result["distribution"];
    const std::size_t points = distribution["x_mm"].size();
    CHECK(points > 2);
    for (const auto& column : distribution.items()) {
        CAPTURE(column.key());
        CHECK(column.value().size() == points);
    }
    for (const json& pressure : distribution["pressure_MPa"]) CHECK(pressure.get<double>() > 0.0);
}

TEST_CASE("the result echoes the resolved scenario and follows the patch") {
    const Outcome slow = evaluate({{"analysis", "roll_gap"},
                                   {"scenario", {{"rolls", {{"speed_m_per_s", 5}}}}},
                                   {"options", {{"distributions", false}}}});
    REQUIRE(slow.ok());
    CHECK(slow.body["scenario"]["rolls"]["speed_m_per_s"] == 5.0);
    CHECK(slow.body["scenario"]["rolls"]["radius_mm"] ==
          api::default_scenario_json()["rolls"]["radius_mm"]);
    CHECK_FALSE(slow.body["result"].contains("distribution"));
    // Rerunning the echoed scenario reproduces the result.
    const Outcome again = evaluate({{"analysis", "roll_gap"},
                                    {"scenario", slow.body["scenario"]},
                                    {"options", {{"distributions", false}}}});
    REQUIRE(again.ok());
    CHECK(again.body == slow.body);
}

TEST_CASE("null scenario and options mean the defaults") {
    const Outcome outcome =
        evaluate({{"analysis", "roll_gap"}, {"scenario", nullptr}, {"options", nullptr}});
    REQUIRE(outcome.ok());
    CHECK(outcome.body["scenario"] == api::default_scenario_json());
}

TEST_CASE("a bite that cannot be driven is a result with a status, not a problem") {
    // Skidding (or a failed solve) is still an answer about the scenario: 200, not 4xx/5xx.
    const Outcome outcome = evaluate(
        {{"analysis", "roll_gap"},
         {"scenario",
          {{"lubricant", {{"limiting_shear", false}}}, {"rolls", {{"speed_m_per_s", 60}}}}},
         {"options", {{"distributions", false}}}});
    REQUIRE(outcome.ok());
    const std::string status = outcome.body["result"]["status"];
    CHECK((status == "ok" || status == "skidding" || status == "contact_lost" ||
           status == "solver_failure"));
    if (status == "skidding") {
        CHECK(outcome.body["result"].contains("skidding"));
        CHECK(outcome.body["result"]["force_kN"].is_null());
    }
}

TEST_CASE("an unknown analysis is a problem that lists the offered ones") {
    const Outcome outcome = evaluate({{"analysis", "stabilty"}});
    REQUIRE_FALSE(outcome.ok());
    CHECK(outcome.problem == api::ProblemCode::unknown_analysis);
    CHECK(outcome.http_status == 422);
    CHECK(outcome.media_type() == "application/problem+json");
    CHECK(outcome.body["type"] == "https://rollgap.dev/problems/unknown_analysis");
    CHECK(outcome.body["errors"][0]["pointer"] == "/analysis");
    CHECK(outcome.body["errors"][0]["bound"].get<std::string>().find("roll_gap") !=
          std::string::npos);
    const Outcome typo = evaluate({{"analysis", "roll-gap"}});
    CHECK(typo.body["errors"][0]["detail"].get<std::string>().find("did you mean 'roll_gap'") !=
          std::string::npos);
}

TEST_CASE("the request envelope is strict") {
    SUBCASE("unknown top-level field") {
        const Outcome outcome = evaluate({{"analysis", "roll_gap"}, {"scenarios", json::object()}});
        CHECK(outcome.problem == api::ProblemCode::invalid_request);
        CHECK(outcome.body["errors"][0]["pointer"] == "/scenarios");
        CHECK(outcome.body["errors"][0]["detail"].get<std::string>().find(
                  "did you mean 'scenario'") != std::string::npos);
    }
    SUBCASE("missing analysis") {
        const Outcome outcome = evaluate(json::object());
        CHECK(outcome.problem == api::ProblemCode::invalid_request);
        CHECK(outcome.body["errors"][0]["pointer"] == "/analysis");
    }
    SUBCASE("analysis of the wrong type") {
        const Outcome outcome = evaluate({{"analysis", 7}});
        CHECK(outcome.problem == api::ProblemCode::invalid_request);
    }
    SUBCASE("not an object") {
        const Outcome outcome = evaluate(json::array());
        CHECK(outcome.problem == api::ProblemCode::invalid_request);
        CHECK(outcome.body["errors"][0]["pointer"] == "");
    }
    SUBCASE("nested too deep (built in code)") {
        json deep = 1;
        for (int i = 0; i < 1000; ++i) deep = json{{"a", std::move(deep)}};
        const Outcome outcome = evaluate({{"analysis", "roll_gap"}, {"scenario", deep}});
        CHECK(outcome.problem == api::ProblemCode::invalid_request);
    }
}

TEST_CASE("scenario and options violations are reported together") {
    const Outcome outcome = evaluate({{"analysis", "roll_gap"},
                                      {"scenario", {{"strip", {{"reduction", 0.9}}}}},
                                      {"options", {{"distribution", true}}}});
    CHECK(outcome.problem == api::ProblemCode::invalid_scenario);
    CHECK(outcome.http_status == 422);
    REQUIRE(outcome.body["errors"].size() == 2);
    CHECK(outcome.body["errors"][0]["pointer"] == "/scenario/strip/reduction");
    CHECK(outcome.body["errors"][1]["pointer"] == "/options/distribution");

    const Outcome options_only =
        evaluate({{"analysis", "roll_gap"}, {"options", {{"distributions", "yes"}}}});
    CHECK(options_only.problem == api::ProblemCode::invalid_options);
    CHECK(options_only.body["errors"][0]["pointer"] == "/options/distributions");
}

TEST_CASE("request text: syntax, size") {
    CHECK(evaluate_text("{\"analysis\": ").problem == api::ProblemCode::invalid_json);
    CHECK(evaluate_text("{\"analysis\": ").http_status == 400);
    const std::string huge =
        "{\"analysis\": \"roll_gap\", \"pad\": \"" + std::string(max_request_bytes, 'x') + "\"}";
    const Outcome too_large = evaluate_text(huge);
    CHECK(too_large.problem == api::ProblemCode::payload_too_large);
    CHECK(too_large.http_status == 413);
    CHECK(evaluate_text(R"({"analysis": "roll_gap", "options": {"distributions": false}})").ok());
}

TEST_CASE("an exception inside an analysis becomes the problem 'internal'") {
    const std::array<Analysis, 2> throwing{
        Analysis{"throws_when_run", "Throws when run", "test",
                 [](const core::Scenario&, const json&, const std::string&, api::FieldErrors&) {
                     return PreparedAnalysis{json::object(),
                                             []() -> json { throw std::runtime_error("boom"); }};
                 }},
        Analysis{"throws_when_prepared", "Throws when prepared", "test",
                 [](const core::Scenario&, const json&, const std::string&,
                    api::FieldErrors&) -> PreparedAnalysis {
                     throw 42;  // not even a std::exception
                 }},
    };
    // The log line of each failure is expected here; keep the test output clean.
    const auto level = spdlog::get_level();
    spdlog::set_level(spdlog::level::off);
    for (const char* name : {"throws_when_run", "throws_when_prepared"}) {
        CAPTURE(name);
        const Outcome outcome = evaluate({{"analysis", name}}, throwing);
        CHECK(outcome.problem == api::ProblemCode::internal);
        CHECK(outcome.http_status == 500);
        CHECK(outcome.body["detail"].get<std::string>().find("boom") ==
              std::string::npos);  // no internals leak
    }
    spdlog::set_level(level);
}

TEST_CASE("cli: scenario prints the default scenario") {
    const CliRun result = run({"scenario"});
    CHECK(result.exit_status == exit_success);
    CHECK(json::parse(result.out) == api::default_scenario_json());
    CHECK(result.out.find("\n  \"friction\": {") != std::string::npos);  // pretty, 2 spaces
}

TEST_CASE("cli: run reads a request from standard input") {
    const CliRun result =
        run({"run", "-"}, R"({"analysis": "roll_gap", "options": {"distributions": false}})");
    CHECK(result.exit_status == exit_success);
    const json body = json::parse(result.out);
    CHECK(body["result"]["status"] == "ok");
    CHECK(body["result"]["force_kN"].get<double>() > 0.0);
}

TEST_CASE("cli: run reads a request from a file") {
    const std::string path = "rollgap_test_cli_request.json";
    {
        std::ofstream file(path);
        file << R"({"analysis": "roll_gap", "scenario": {"rolls": {"speed_m_per_s": 10}}})";
    }
    const CliRun result = run({"run", path});
    std::remove(path.c_str());
    CHECK(result.exit_status == exit_success);
    CHECK(json::parse(result.out)["scenario"]["rolls"]["speed_m_per_s"] == 10.0);
}

TEST_CASE("cli: a bad request prints problem details on stdout and exits 2") {
    SUBCASE("invalid JSON") {
        const CliRun result = run({"run", "-"}, "{nope");
        CHECK(result.exit_status == exit_bad_input);
        CHECK(json::parse(result.out)["type"] == "https://rollgap.dev/problems/invalid_json");
    }
    SUBCASE("invalid scenario") {
        const CliRun result = run(
            {"run", "-"}, R"({"analysis": "roll_gap", "scenario": {"strip": {"reduction": 2}}})");
        CHECK(result.exit_status == exit_bad_input);
        CHECK(json::parse(result.out)["errors"][0]["pointer"] == "/scenario/strip/reduction");
    }
    SUBCASE("unreadable file") {
        const CliRun result = run({"run", "/nonexistent/rollgap/request.json"});
        CHECK(result.exit_status == exit_bad_input);
        CHECK(json::parse(result.out)["type"] == "https://rollgap.dev/problems/unreadable_input");
    }
}

TEST_CASE("cli: help, version and usage errors") {
    const CliRun help = run({"--help"});
    CHECK(help.exit_status == exit_success);
    CHECK(help.out.find("usage: rollgap") != std::string::npos);
    CHECK(help.out.find("roll_gap") != std::string::npos);

    const CliRun version_run = run({"--version"});
    CHECK(version_run.exit_status == exit_success);
    CHECK(version_run.out == "rollgap " + std::string(version()) + "\n");

    for (const auto& arguments :
         {std::vector<std::string_view>{}, std::vector<std::string_view>{"frobnicate"},
          std::vector<std::string_view>{"run"}, std::vector<std::string_view>{"scenario", "x"}}) {
        const CliRun usage = run(arguments);
        CHECK(usage.exit_status == exit_bad_input);
        CHECK(usage.out.empty());
        CHECK(usage.err.find("usage: rollgap") != std::string::npos);
    }
}

TEST_CASE("cli: every command is parsed by one command line, and misuse names the command") {
    SUBCASE("a mistyped command is suggested") {
        const CliRun usage = run({"scenaro"});
        CHECK(usage.exit_status == exit_bad_input);
        CHECK(usage.err.find("unknown command 'scenaro'; did you mean 'scenario'?") !=
              std::string::npos);
    }
    SUBCASE("too many operands") {
        const CliRun usage = run({"run", "a.json", "b.json"});
        CHECK(usage.exit_status == exit_bad_input);
        CHECK(usage.err.find("'b.json'") != std::string::npos);
    }
    SUBCASE("help as a command") {
        const CliRun help = run({"help"});
        CHECK(help.exit_status == exit_success);
        CHECK(help.out.find("usage: rollgap") != std::string::npos);
    }
    SUBCASE("serve --help prints the settings table") {
        const CliRun help = run({"serve", "--help"});
        CHECK(help.exit_status == exit_success);
        CHECK(help.out.find("usage: rollgap serve") != std::string::npos);
        CHECK(help.out.find("ROLLGAP_QUEUE_LENGTH") != std::string::npos);
    }
    SUBCASE("serve refuses a bad value before it listens") {
        const CliRun bad = run({"serve", "--port", "70000"});
        CHECK(bad.exit_status == exit_bad_input);
        CHECK(bad.err.find("rollgap serve: invalid --port") != std::string::npos);
        const CliRun unknown = run({"serve", "--prot=80"});
        CHECK(unknown.exit_status == exit_bad_input);
        CHECK(unknown.err.find("did you mean '--port'?") != std::string::npos);
    }
    SUBCASE("healthcheck takes only http URLs") {
        const CliRun bad = run({"healthcheck", "--url", "ftp://127.0.0.1/readyz"});
        CHECK(bad.exit_status == exit_bad_input);
    }
    SUBCASE("without the HTTP layer, serve and healthcheck say so") {
        std::istringstream in;
        std::ostringstream out, err;
        CHECK(run_cli(std::vector<std::string_view>{"healthcheck"}, in, out, err) ==
              exit_internal_error);
        CHECK(err.str().find("no HTTP layer") != std::string::npos);
    }
    SUBCASE("openapi prints the document") {
        const CliRun document = run({"openapi"});
        CHECK(document.exit_status == exit_success);
        CHECK(json::parse(document.out).contains("openapi"));
    }
}
