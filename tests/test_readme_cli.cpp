// The README's command-line examples ("Command line"), run as they are written: every fenced
// block with `echo '<request>' | build/rollgap run -` runs through the command line (run_cli, in
// process), and every figure the block shows under the command (a number, string or boolean at
// its place in the trimmed JSON, `…` marking what was left out) must be what the program prints,
// to the digits the README prints.

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/cli.h"

using nlohmann::json;

namespace {

std::string readme_text() {
    // This file is tests/test_readme_cli.cpp; the README is beside tests/.
    const std::filesystem::path readme =
        std::filesystem::path(__FILE__).parent_path().parent_path() / "README.md";
    std::ifstream file(readme);
    REQUIRE_MESSAGE(file, "cannot read " << readme.string());
    return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

struct Example {
    std::string request;  // what echo pipes into the program
    std::string shown;    // the output the README shows under the command (may be empty)
};

// Every fenced block whose command pipes an echo into `build/rollgap run -`.
std::vector<Example> cli_examples(const std::string& readme) {
    std::vector<Example> examples;
    constexpr std::string_view fence = "```";
    for (std::size_t open = readme.find(fence); open != std::string::npos;) {
        const std::size_t start = readme.find('\n', open) + 1;
        const std::size_t close = readme.find("\n```", start);
        if (close == std::string::npos) break;
        const std::string block = readme.substr(start, close - start + 1);
        open = readme.find(fence, close + 4);
        const std::size_t run = block.find("| build/rollgap run -");
        const std::size_t echo = block.find("echo '");
        if (run == std::string::npos || echo == std::string::npos || echo > run) continue;
        const std::size_t request_end = block.find('\'', echo + 6);
        REQUIRE(request_end != std::string::npos);
        const std::size_t command_end = block.find('\n', run);
        examples.push_back(
            {block.substr(echo + 6, request_end - echo - 6),
             command_end == std::string::npos ? std::string() : block.substr(command_end + 1)});
    }
    return examples;
}

struct ShownValue {
    std::string pointer;  // JSON pointer into the program's output
    json value;           // number, string or boolean as shown
    std::string literal;  // the number as printed: its digits set the tolerance
};

// The values of a trimmed JSON text: objects and arrays as in JSON, `…` standing for members or
// elements that were left out (it still counts as an element of an array).
std::vector<ShownValue> shown_values(std::string_view text) {
    struct Frame {
        bool array = false;
        std::string key;  // objects: the key whose value comes next
        std::size_t index = 0;
        std::string pointer;  // of this container
    };
    std::vector<ShownValue> values;
    std::vector<Frame> frames;
    const auto here = [&]() -> std::string {
        const Frame& top = frames.back();
        return top.pointer + "/" + (top.array ? std::to_string(top.index) : top.key);
    };
    constexpr std::string_view ellipsis = "…";
    std::size_t i = 0;
    while (i < text.size()) {
        const char c = text[i];
        if (std::isspace(static_cast<unsigned char>(c)) || c == ':') {
            ++i;
        } else if (text.substr(i, ellipsis.size()) == ellipsis) {
            i += ellipsis.size();
        } else if (c == '{' || c == '[') {
            const std::string pointer = frames.empty() ? std::string() : here();
            frames.push_back({c == '[', "", 0, pointer});
            ++i;
        } else if (c == '}' || c == ']') {
            REQUIRE_FALSE(frames.empty());
            frames.pop_back();
            ++i;
        } else if (c == ',') {
            REQUIRE_FALSE(frames.empty());
            if (frames.back().array) ++frames.back().index;
            frames.back().key.clear();
            ++i;
        } else if (c == '"') {
            const std::size_t end = text.find('"', i + 1);
            REQUIRE(end != std::string_view::npos);
            const std::string word(text.substr(i + 1, end - i - 1));
            i = end + 1;
            REQUIRE_FALSE(frames.empty());
            std::size_t next = i;
            while (next < text.size() && std::isspace(static_cast<unsigned char>(text[next])))
                ++next;
            if (!frames.back().array && next < text.size() && text[next] == ':') {
                frames.back().key = word;
            } else {
                values.push_back({here(), word, ""});
            }
        } else {
            std::size_t end = i;
            while (end < text.size() &&
                   std::string_view(",}] \n").find(text[end]) == std::string_view::npos)
                ++end;
            const std::string literal(text.substr(i, end - i));
            i = end;
            REQUIRE_FALSE(frames.empty());
            if (literal == "true" || literal == "false") {
                values.push_back({here(), literal == "true", ""});
            } else if (literal != "null") {
                values.push_back({here(), std::stod(literal), literal});
            }
        }
    }
    CHECK(frames.empty());
    return values;
}

// Half a unit of the last digit the README prints: 9242.88 → 0.005, 20.096652089608604 → 5e-15.
double printed_tolerance(const std::string& literal, double value) {
    const std::size_t point = literal.find('.');
    const std::size_t exponent_at = literal.find_first_of("eE");
    const std::string mantissa = literal.substr(0, exponent_at);
    const int decimals =
        point == std::string::npos ? 0 : static_cast<int>(mantissa.size() - point - 1);
    const int exponent =
        exponent_at == std::string::npos ? 0 : std::stoi(literal.substr(exponent_at + 1));
    // A double printed with 17 digits is exact only to its own rounding: allow that too.
    return 0.5 * std::pow(10.0, exponent - decimals) + 4.0 * std::abs(value) * 2.2e-16;
}

}  // namespace

TEST_CASE("README: every command-line example runs and prints the figures the README shows") {
    const std::vector<Example> examples = cli_examples(readme_text());
    // The README's examples: roll_gap at 25 m/s, stability, amplitude, tension_cycle, sweep,
    // evaluate.
    REQUIRE(examples.size() >= 6);
    std::size_t compared = 0;
    for (const Example& example : examples) {
        CAPTURE(example.request);
        std::istringstream in(example.request);
        std::ostringstream out, err;
        const std::string_view arguments[] = {"run", "-"};
        const int status = rollgap::service::run_cli(arguments, in, out, err);
        REQUIRE(status == rollgap::service::exit_success);
        const json printed = json::parse(out.str());
        if (example.shown.find('{') == std::string::npos) continue;  // a command without its output
        const std::vector<ShownValue> shown = shown_values(example.shown);
        CHECK(!shown.empty());
        for (const ShownValue& value : shown) {
            CAPTURE(value.pointer);
            const json::json_pointer pointer(value.pointer);
            REQUIRE(printed.contains(pointer));
            const json& actual = printed.at(pointer);
            if (value.value.is_number()) {
                REQUIRE(actual.is_number());
                const double expected = value.value.get<double>();
                CAPTURE(value.literal);
                CAPTURE(actual.dump());
                CHECK(std::abs(actual.get<double>() - expected) <=
                      printed_tolerance(value.literal, expected));
            } else {
                CHECK(actual == value.value);
            }
            ++compared;
        }
    }
    MESSAGE(compared << " figures of " << examples.size() << " README examples compared");
}

TEST_CASE("README examples: the reader of shown output follows the JSON structure") {
    const std::vector<ShownValue> values = shown_values(R"({
  "result": {
    "points": [
      {"a_kN": 1.5, "status": "found", …},
      …,
      {"b": [10, 2.25e-3]}
    ],
    "stable": true
  },
  …
})");
    REQUIRE(values.size() == 5);
    CHECK(values[0].pointer == "/result/points/0/a_kN");
    CHECK(values[1].value == "found");
    CHECK(values[2].pointer == "/result/points/2/b/0");
    CHECK(values[3].pointer == "/result/points/2/b/1");
    CHECK(values[3].value.get<double>() == doctest::Approx(2.25e-3));
    CHECK(values[4].pointer == "/result/stable");
    CHECK(values[4].value == true);
    CHECK(printed_tolerance("9242.88", 9242.88) == doctest::Approx(0.005));
    CHECK(printed_tolerance("2.25e-3", 2.25e-3) == doctest::Approx(0.5e-5));
}
