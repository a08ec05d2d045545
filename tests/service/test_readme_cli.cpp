// The documentation's command-line examples (README.md and docs/*.md), run as they are written.
// A fenced block is an example when its command is `echo '<request>' | build/rollgap run ARGS`
// or `build/rollgap run ARGS` (the command may continue over lines that end in a backslash):
// it runs through the command line (run_cli, in process; a request file is read from the
// repository), and what the block shows under the command must be what the program prints. In
// trimmed JSON every figure (a number, string or boolean at its place, `…` marking what was left
// out) must match to the digits the block prints; a CSV example (`--format csv`) must match line
// for line. A block that mentions `build/rollgap run` but is not such an example fails the
// test, and so does a file expected to hold examples that holds fewer than expected, so that no
// example goes unrun.

#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "service/cli.h"

#include "support/repository.h"
#include "support/approx.h"

using nlohmann::json;

namespace {

using rollgap::test::repository_root;

std::string read_text(const std::filesystem::path& path) {
    std::ifstream file(path);
    REQUIRE_MESSAGE(file, "cannot read " << path.string());
    return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
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

// The files that hold command-line examples, and how many each holds at least.
struct ExpectedExamples {
    std::string_view file;
    std::size_t at_least;
};
constexpr ExpectedExamples expected_examples[] = {
    {"README.md", 4},     // the critical speed, a lubricant sweep, a CSV table, a tandem mill
    {"docs/cli.md", 13},  // roll_gap, stability, amplitude, tension_cycle, map, tandem_sweep,
                          // tandem_map, evaluate, calibrate, speed_limit, batch,
                          // tandem_speed_limit, a CSV table
};

std::string_view trim(std::string_view text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())))
        text.remove_prefix(1);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back())))
        text.remove_suffix(1);
    return text;
}

struct Block {
    std::size_t line = 0;            // of the opening fence, from 1
    std::vector<std::string> lines;  // between the fences
};

// The fenced blocks of a Markdown text: from a line that starts with ``` (after indentation) to
// the next such line.
std::vector<Block> fenced_blocks(const std::string& text) {
    std::vector<Block> blocks;
    std::istringstream lines(text);
    std::string line;
    std::optional<Block> open;
    for (std::size_t number = 1; std::getline(lines, line); ++number) {
        if (trim(line).starts_with("```")) {
            if (open) {
                blocks.push_back(std::move(*open));
                open.reset();
            } else {
                open = Block{number, {}};
            }
        } else if (open) {
            open->lines.push_back(line);
        }
    }
    if (open) FAIL("a fenced block opened at line " << open->line << " is not closed");
    return blocks;
}

struct Example {
    std::string where;                   // file:line, for messages
    std::vector<std::string> arguments;  // after build/rollgap
    std::optional<std::string> input;    // what echo pipes into the program
    std::string shown;                   // what the block shows under the command (may be empty)
};

// The example a block holds, if it holds one.
std::optional<Example> example_in(const Block& block, const std::string& where) {
    if (block.lines.empty()) return std::nullopt;
    std::string command(trim(block.lines[0]));
    std::size_t last = 0;  // the command's last line
    while (!command.empty() && command.back() == '\\' && last + 1 < block.lines.size()) {
        command.pop_back();
        command += " ";
        command += trim(block.lines[++last]);
    }
    Example example;
    example.where = where;
    std::string_view invocation = command;
    if (invocation.starts_with("echo '")) {
        const std::size_t end = invocation.find('\'', 6);
        if (end == std::string_view::npos) return std::nullopt;
        example.input = std::string(invocation.substr(6, end - 6));
        invocation = trim(invocation.substr(end + 1));
        if (!invocation.starts_with("|")) return std::nullopt;
        invocation = trim(invocation.substr(1));
    }
    if (!invocation.starts_with("build/rollgap run ")) return std::nullopt;
    std::istringstream words{std::string(invocation.substr(std::string_view("build/").size()))};
    std::string word;
    words >> word;  // rollgap
    while (words >> word) example.arguments.push_back(word);
    for (std::size_t i = last + 1; i < block.lines.size(); ++i)
        example.shown += block.lines[i] + "\n";
    return example;
}

struct DocumentExamples {
    std::vector<Example> examples;
    std::vector<std::string> unrunnable;  // file:line of blocks that mention the program
};

DocumentExamples cli_examples(const std::string& file) {
    DocumentExamples found;
    for (const Block& block : fenced_blocks(read_text(repository_root() / file))) {
        const std::string where = file + ":" + std::to_string(block.line);
        if (auto example = example_in(block, where)) {
            found.examples.push_back(std::move(*example));
            continue;
        }
        for (const std::string& line : block.lines) {
            if (line.find("build/rollgap run") != std::string::npos) {
                found.unrunnable.push_back(where);
                break;
            }
        }
    }
    return found;
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

// Half a unit of the last digit the documentation prints: 9242.88 → 0.005,
// 20.096652089608604 → 5e-15.
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

// Whether the arguments ask for CSV (`--format csv`).
bool prints_csv(const std::vector<std::string>& arguments) {
    for (std::size_t i = 0; i + 1 < arguments.size(); ++i) {
        if (arguments[i] == "--format" && arguments[i + 1] == "csv") return true;
    }
    return false;
}

// Runs the example; the request file, if it names one, is read from the repository root.
// Returns the program's standard output.
std::string run_example(const Example& example) {
    std::vector<std::string> arguments = example.arguments;
    REQUIRE_MESSAGE(!arguments.empty(), "no command");
    REQUIRE(arguments.front() == "run");
    std::optional<std::string> source;
    for (std::size_t i = 1; i < arguments.size(); ++i) {
        if (arguments[i] == "--format" || arguments[i] == "--table") {
            ++i;  // the option's value
        } else if (!arguments[i].starts_with("-")) {
            arguments[i] = (repository_root() / arguments[i]).string();
            source = arguments[i];
        } else if (arguments[i] == "-") {
            source = arguments[i];
        }
    }
    REQUIRE_MESSAGE(source, "the command names no request file and no '-'");
    REQUIRE_MESSAGE(example.input.has_value() == (*source == "-"),
                    "a request is piped in exactly when the program reads standard input");
    const std::vector<std::string_view> views(arguments.begin(), arguments.end());
    std::istringstream in(example.input.value_or(""));
    std::ostringstream out, err;
    const int status = rollgap::service::run_cli(views, in, out, err);
    CAPTURE(err.str());
    REQUIRE(status == rollgap::service::exit_success);
    return out.str();
}

// Compares the CSV the program printed with the lines shown: CRLF line ends, every line equal.
void compare_csv(const std::string& printed, const std::string& shown) {
    REQUIRE_MESSAGE(!shown.empty(), "a CSV example shows its output");
    for (std::size_t at = printed.find('\n'); at != std::string::npos;
         at = printed.find('\n', at + 1)) {
        CHECK_MESSAGE((at > 0 && printed[at - 1] == '\r'), "a CSV line ends in CRLF");
    }
    std::string lines;
    for (std::size_t from = 0; from < printed.size();) {
        const std::size_t end = printed.find("\r\n", from);
        if (end == std::string::npos) {
            lines += printed.substr(from);
            break;
        }
        lines += printed.substr(from, end - from) + "\n";
        from = end + 2;
    }
    CHECK(lines == shown);
}

// Compares the JSON the program printed with the figures shown; returns how many were compared.
std::size_t compare_json(const std::string& printed_text, const std::string& shown_text) {
    const json printed = json::parse(printed_text);
    if (shown_text.find('{') == std::string::npos) return 0;  // a command without its output
    const std::vector<ShownValue> shown = shown_values(shown_text);
    CHECK(!shown.empty());
    std::size_t compared = 0;
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
    return compared;
}

}  // namespace

TEST_CASE("README and docs: every command-line example runs and prints the figures it shows") {
    std::map<std::string, std::size_t, std::less<>> per_file;
    std::size_t examples = 0, compared = 0, csv_lines = 0;
    for (const std::string& file : documentation_files()) {
        const DocumentExamples found = cli_examples(file);
        for (const std::string& where : found.unrunnable) {
            CAPTURE(where);
            FAIL_CHECK("a fenced block mentions build/rollgap run but is no runnable example");
        }
        per_file[file] = found.examples.size();
        for (const Example& example : found.examples) {
            CAPTURE(example.where);
            CAPTURE(example.input.value_or(""));
            const std::string printed = run_example(example);
            if (prints_csv(example.arguments)) {
                compare_csv(printed, example.shown);
                csv_lines += static_cast<std::size_t>(
                    std::count(example.shown.begin(), example.shown.end(), '\n'));
            } else {
                compared += compare_json(printed, example.shown);
            }
            ++examples;
        }
    }
    for (const ExpectedExamples& expected : expected_examples) {
        CAPTURE(expected.file);
        const auto found = per_file.find(expected.file);
        REQUIRE_MESSAGE(found != per_file.end(), "the file is not in README.md or docs/");
        CHECK_MESSAGE(found->second >= expected.at_least,
                      "the file holds " << found->second << " command-line examples, expected "
                                        << expected.at_least);
    }
    std::ostringstream counts;
    for (const auto& [file, count] : per_file) {
        if (count > 0) counts << " " << file << ": " << count << ";";
    }
    MESSAGE(compared << " figures and " << csv_lines << " CSV lines of " << examples
                     << " command-line examples compared (" << counts.str() << " )");
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
    CHECK(values[3].value.get<double>() == rollgap::test::approx(2.25e-3));
    CHECK(values[4].pointer == "/result/stable");
    CHECK(values[4].value == true);
    CHECK(printed_tolerance("9242.88", 9242.88) == rollgap::test::approx(0.005));
    CHECK(printed_tolerance("2.25e-3", 2.25e-3) == rollgap::test::approx(0.5e-5));
}

TEST_CASE("README examples: a block is an example when its command runs the program") {
    const auto block = [](std::vector<std::string> lines) { return Block{1, std::move(lines)}; };
    const auto piped = example_in(block({"echo '{\"analysis\": \"evaluate\"}' \\",
                                         "  | build/rollgap run --format csv -", "a,b"}),
                                  "x");
    REQUIRE(piped);
    CHECK(piped->input == "{\"analysis\": \"evaluate\"}");
    CHECK(piped->arguments == std::vector<std::string>{"run", "--format", "csv", "-"});
    CHECK(piped->shown == "a,b\n");
    CHECK(prints_csv(piped->arguments));
    const auto file = example_in(block({"build/rollgap run examples/calibrate.json", "{"}), "x");
    REQUIRE(file);
    CHECK_FALSE(file->input);
    CHECK(file->arguments == std::vector<std::string>{"run", "examples/calibrate.json"});
    CHECK_FALSE(example_in(block({"bash scripts/run-service.sh"}), "x"));
    CHECK_FALSE(example_in(block({"build/rollgap scenario", "build/rollgap run -"}), "x"));
    const std::vector<Block> blocks = fenced_blocks("text\n```\na\n```\n  ```sh\n  b\n  ```\n");
    REQUIRE(blocks.size() == 2);
    CHECK(blocks[0].line == 2);
    CHECK(blocks[1].lines == std::vector<std::string>{"  b"});
}
