// The documentation's curl examples, run as they are written against a server in process: the
// fenced sh block right after a marker such as <!-- http-examples --> is extracted,
// localhost:8080 is replaced by the test server's loopback address, and bash runs it with -e
// and pipefail. Every marker the documentation (README.md, docs/*.md) holds must be one of the
// blocks below, each with what its output must show, and every fenced block that sends curl to
// localhost:8080 must be such a marked block: no example goes unrun.

#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/cli.h"

#include "support/http_test.h"
#include "support/repository.h"

using namespace rollgap;
using namespace rollgap::test;

namespace {

// The marked example blocks: where each is and its marker.
struct MarkedBlock {
    std::string_view file;    // relative to the repository root
    std::string_view marker;  // the comment right before the block
};
constexpr MarkedBlock readme_block{"README.md", "<!-- http-readme-examples -->"};
constexpr MarkedBlock api_block{"docs/http-api.md", "<!-- http-examples -->"};
constexpr MarkedBlock scenario_block{"docs/http-api.md", "<!-- http-scenario-examples -->"};
constexpr MarkedBlock marked_blocks[] = {readme_block, api_block, scenario_block};
constexpr std::string_view marker_start = "<!-- http-";

using rollgap::test::repository_root;

std::string read_text(const std::string& file) {
    const std::filesystem::path path = repository_root() / file;
    std::ifstream in(path);
    REQUIRE_MESSAGE(in, "cannot read " << path.string());
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// README.md and every docs/*.md, relative to the repository root.
std::vector<std::string> documentation_files() {
    const std::filesystem::path docs = repository_root() / "docs";
    REQUIRE_MESSAGE(std::filesystem::is_directory(docs), "no directory " << docs.string());
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(docs)) {
        if (entry.is_regular_file() && entry.path().extension() == ".md")
            files.push_back("docs/" + entry.path().filename().string());
    }
    std::sort(files.begin(), files.end());
    files.insert(files.begin(), "README.md");
    return files;
}

struct Fence {
    std::size_t open;   // offset of the opening fence line
    std::size_t start;  // offset of the block's first line
    std::size_t close;  // offset of the closing fence line
    std::string info;   // what follows ``` on the opening line
    std::size_t line;   // of the opening fence, from 1
};

// The fenced blocks of a Markdown text: from a line that starts with ``` (after indentation) to
// the next such line.
std::vector<Fence> fences(const std::string& text) {
    std::vector<Fence> found;
    std::optional<Fence> open;
    std::size_t number = 1;
    for (std::size_t at = 0; at < text.size(); ++number) {
        std::size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        std::string_view line(text.data() + at, end - at);
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t'))
            line.remove_prefix(1);
        if (line.starts_with("```")) {
            if (open) {
                open->close = at;
                found.push_back(*open);
                open.reset();
            } else {
                open = Fence{at, end + 1, 0, std::string(line.substr(3)), number};
            }
        }
        at = end + 1;
    }
    if (open) FAIL("a fenced block opened at line " << open->line << " is not closed");
    return found;
}

// The block right after `block.marker` in its file: a fenced sh block, nothing but blank space
// between them.
std::string marked_examples(const MarkedBlock& block) {
    const std::string text = read_text(std::string(block.file));
    const std::string marker(block.marker);
    const std::size_t at = text.find(marker);
    REQUIRE_MESSAGE(at != std::string::npos, block.file << " has no " << marker << " marker");
    REQUIRE_MESSAGE(text.find(marker, at + 1) == std::string::npos,
                    block.file << " has the marker " << marker << " twice");
    for (const Fence& fence : fences(text)) {
        if (fence.open < at) continue;
        const std::string_view between(text.data() + at + marker.size(),
                                       fence.open - at - marker.size());
        REQUIRE_MESSAGE(
            std::all_of(between.begin(), between.end(),
                        [](char c) { return std::isspace(static_cast<unsigned char>(c)); }),
            "the marker " << marker << " must be right before its fenced block");
        REQUIRE_MESSAGE(fence.info == "sh", "the block after " << marker << " is a ```sh block");
        return text.substr(fence.start, fence.close - fence.start);
    }
    FAIL(block.file << ": no fenced block after " << marker);
    return {};
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
    MESSAGE(
        "curl is not installed (scripts/install-deps.sh installs it): the documentation's curl "
        "examples not run");
    return false;
}

// Whether a fenced block sends curl to the service of the examples.
bool sends_curl_to_the_service(std::string_view block) {
    if (block.find("localhost:8080") == std::string_view::npos) return false;
    std::istringstream lines{std::string(block)};
    std::string line;
    while (std::getline(lines, line)) {
        const std::size_t first = line.find_first_not_of(" \t");
        if (first == std::string::npos) continue;
        const std::string_view text = std::string_view(line).substr(first);
        if (text.starts_with("curl ") || text.find("$(curl ") != std::string_view::npos)
            return true;
    }
    return false;
}

}  // namespace

TEST_CASE("README and docs: every curl example is a marked block that a test runs") {
    std::size_t marked = 0;
    for (const std::string& file : documentation_files()) {
        CAPTURE(file);
        const std::string text = read_text(file);
        // Every marker is one of the blocks the tests below run.
        std::vector<std::size_t> selected;  // where each marker of this file points
        for (std::size_t at = text.find(marker_start); at != std::string::npos;
             at = text.find(marker_start, at + 1)) {
            const std::size_t end = text.find("-->", at);
            REQUIRE(end != std::string::npos);
            const std::string marker = text.substr(at, end + 3 - at);
            CAPTURE(marker);
            const bool known = std::any_of(std::begin(marked_blocks), std::end(marked_blocks),
                                           [&](const MarkedBlock& block) {
                                               return block.file == file && block.marker == marker;
                                           });
            CHECK_MESSAGE(known, "a marked block that no test runs");
            selected.push_back(at);
            ++marked;
        }
        // Every fenced block that sends curl to the service follows a marker.
        for (const Fence& fence : fences(text)) {
            const std::string_view block(text.data() + fence.start, fence.close - fence.start);
            if (!sends_curl_to_the_service(block)) continue;
            CAPTURE(fence.line);
            const bool follows_marker =
                std::any_of(selected.begin(), selected.end(), [&](std::size_t at) {
                    const std::size_t end = text.find("-->", at) + 3;
                    return end <= fence.open &&
                           std::all_of(
                               text.begin() + static_cast<std::ptrdiff_t>(end),
                               text.begin() + static_cast<std::ptrdiff_t>(fence.open),
                               [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
                });
            CHECK_MESSAGE(follows_marker, "a curl example without a marker: no test would run it");
        }
    }
    // And every block the tests run is there, right after its marker.
    for (const MarkedBlock& block : marked_blocks) {
        CAPTURE(block.marker);
        CHECK(marked_examples(block).find("curl") != std::string::npos);
    }
    CHECK(marked == std::size(marked_blocks));
}

// What the command line prints for `request` (the facade the service shares, docs/cli.md).
std::string cli_answer(const std::string& request, bool csv) {
    std::vector<std::string_view> arguments{"run"};
    if (csv) {
        arguments.push_back("--format");
        arguments.push_back("csv");
    }
    arguments.push_back("-");
    std::istringstream in(request);
    std::ostringstream out, err;
    REQUIRE(rollgap::service::run_cli(arguments, in, out, err) == 0);
    return out.str();
}

TEST_CASE("README: the quick-start curl examples run against the service") {
    if (!have_curl()) return;
    TestServer server;
    const auto [status, output] = run_examples(marked_examples(readme_block), server);
    const std::string shown = output.substr(0, 3000);
    CAPTURE(shown);
    CHECK(status == 0);
    // the figures the command line gives for the same requests (the README shows them too,
    // checked by test_readme_cli.cpp): the service answers what the CLI answers
    const nlohmann::json stability = nlohmann::json::parse(
        cli_answer(R"({"analysis":"stability","options":{"detail":"summary"}})", false));
    const nlohmann::json sweep = nlohmann::json::parse(
        cli_answer(R"({"analysis":"sweep","options":{"parameter":"/lubricant/viscosity_Pa_s",)"
                   R"("values":[0.0003,0.00055,0.0008,0.0012]}})",
                   false));
    const std::string csv =
        cli_answer(R"({"analysis":"sweep","options":{"parameter":"/lubricant/viscosity_Pa_s",)"
                   R"("values":[0.0003,0.00055]}})",
                   true);
    const std::string mill_stands =
        cli_answer(R"({"analysis":"tandem","options":{"critical_speed":false}})", true);
    const auto figure = [](const char* name, const nlohmann::json& value) {
        return "\"" + std::string(name) + "\":" + value.dump();
    };
    REQUIRE(stability["result"]["critical_speed"]["status"] == "found");
    REQUIRE(sweep["result"]["points"].size() == 4);
    for (const std::string& expected : {
             std::string(R"("analysis":"stability")"),  // 1. the critical speed
             figure("critical_speed_m_per_s",
                    stability["result"]["critical_speed"]["critical_speed_m_per_s"]),
             std::string(R"("parameter":"/lubricant/viscosity_Pa_s")"),  // 2. the sweep
             figure("critical_speed_m_per_s",                            // at 1.2 mPa s
                    sweep["result"]["points"][3]["critical_speed_m_per_s"]),
             std::string("value_Pa_s,status,critical_speed_m_per_s,frequency_Hz,chatter_type,"
                         "chatter_band\r\n"),
             csv,          // 3. the CSV, whole
             mill_stands,  // 4. the mill's stands, whole
         }) {
        CAPTURE(expected);
        CHECK(output.find(expected) != std::string::npos);
    }
}

TEST_CASE("README and docs: docs/http-api.md's curl examples run against the service") {
    if (!have_curl()) return;
    TestServer server;
    const std::string examples = marked_examples(api_block);
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

TEST_CASE("README and docs: docs/http-api.md's stored scenario examples run against the service") {
    if (!have_curl()) return;
    // A fresh store of its own: the examples create and delete stand-3.
    char pattern[] = "/tmp/rollgap-readme-store-XXXXXX";
    REQUIRE(::mkdtemp(pattern) != nullptr);
    const std::filesystem::path dir = pattern;
    {
        service::ServerConfig config = test_config();
        config.store = "sqlite:" + (dir / "jobs.db").string();
        TestServer server(config);
        const auto [status, output] = run_examples(marked_examples(scenario_block), server);
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
