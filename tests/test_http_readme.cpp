// The README's curl examples ("HTTP service"), run as they are written against a server in
// process: the block after the marker <!-- http-examples --> is extracted, localhost:8080 is
// replaced by the test server's loopback address, and bash runs it with -e and pipefail.

#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;

namespace {

std::string readme_examples(const std::string& marker = "<!-- http-examples -->") {
    // This file is tests/test_http_readme.cpp; the README is beside tests/.
    const std::filesystem::path readme =
        std::filesystem::path(__FILE__).parent_path().parent_path() / "README.md";
    std::ifstream file(readme);
    REQUIRE_MESSAGE(file, "cannot read " << readme.string());
    const std::string text((std::istreambuf_iterator<char>(file)),
                           std::istreambuf_iterator<char>());
    const std::size_t at = text.find(marker);
    REQUIRE_MESSAGE(at != std::string::npos, "README.md has no " << marker << " marker");
    const std::size_t open = text.find("```sh\n", at);
    REQUIRE(open != std::string::npos);
    const std::size_t start = open + 6;
    const std::size_t close = text.find("\n```", start);
    REQUIRE(close != std::string::npos);
    return text.substr(start, close - start + 1);
}

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size())) {
        text.replace(at, from.size(), to);
    }
    return text;
}

struct ScriptRun {
    int status;
    std::string output;
};

// Runs `examples` with bash -e -o pipefail against `server`.
ScriptRun run_examples(const std::string& examples, const TestServer& server) {
    const std::string script =
        replace_all(examples, "localhost:8080", "127.0.0.1:" + std::to_string(server.port()));
    const auto path = std::filesystem::temp_directory_path() /
                      ("rollgap-readme-" + std::to_string(::getpid()) + ".sh");
    std::ofstream(path) << "set -euo pipefail\n" << script;
    FILE* pipe = ::popen(("bash " + path.string() + " 2>&1").c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string output;
    char buffer[4096];
    while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
    const int status = ::pclose(pipe);
    std::filesystem::remove(path);
    return {status, output};
}

bool have_curl() {
    if (std::filesystem::exists("/usr/bin/curl")) return true;
    MESSAGE("curl is not installed (scripts/install-deps.sh installs it): README examples not run");
    return false;
}

}  // namespace

TEST_CASE("README: the HTTP service's curl examples run against the service") {
    if (!have_curl()) return;
    TestServer server;
    const std::string examples = readme_examples();
    CHECK(examples.find("curl") != std::string::npos);
    const auto [status, output] = run_examples(examples, server);
    const std::string shown = output.substr(0, 3000);
    CAPTURE(shown);
    CHECK(status == 0);
    // What each example shows.
    for (const char* expected : {
             R"("status":"ready")",          // readyz
             R"("entry_thickness_mm":1.6)",  // the default scenario
             R"("speed_m_per_s":25.0)",      // the roll-gap example echoes its scenario
             R"("analysis":"stability")",    // critical speed
             R"("parameter":"/lubricant/viscosity_Pa_s")",      // the sweep
             R"("pointer":"/scenario/rolls/speed_m_per_sec")",  // the mistyped unit suffix
             R"("state":)",                                     // the job document
             "rollgap_http_requests_total{",                    // metrics
         }) {
        CAPTURE(expected);
        CHECK(output.find(expected) != std::string::npos);
    }
}

TEST_CASE("README: the stored scenario examples run against the service") {
    if (!have_curl()) return;
    // A fresh store of its own: the examples create and delete stand-3.
    char pattern[] = "/tmp/rollgap-readme-store-XXXXXX";
    REQUIRE(::mkdtemp(pattern) != nullptr);
    const std::filesystem::path dir = pattern;
    {
        service::ServerConfig config = test_config();
        config.store = "sqlite:" + (dir / "jobs.db").string();
        TestServer server(config);
        const auto [status, output] =
            run_examples(readme_examples("<!-- http-scenario-examples -->"), server);
        const std::string shown = output.substr(0, 3000);
        CAPTURE(shown);
        CHECK(status == 0);
        for (const char* expected : {
                 R"("speed_m_per_s":12.0)",                   // the stored complete scenario
                 R"("name":"stand-3","updated_at":)",         // the list
                 "428\n",                                     // replacing without If-Match
                 "ETag: \"2\"",                               // replaced with it
                 R"("base":{"name":"stand-3","version":2})",  // the analysis on the base
             }) {
            CAPTURE(expected);
            CHECK(output.find(expected) != std::string::npos);
        }
        // The last example deleted it.
        auto client = server.client();
        CHECK(body_json(client.Get("/v1/scenarios")) == json{{"scenarios", json::array()}});
    }
    std::filesystem::remove_all(dir);
}
