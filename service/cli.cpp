#include "service/cli.h"

#include <algorithm>
#include <array>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "api/scenario_json.h"
#include "api/text.h"
#include "service/analyses.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "service/version.h"

namespace rollgap::service {
namespace {

void print_usage(std::ostream& stream) {
    stream << "usage: rollgap <command> [arguments]\n"
              "\n"
              "Roll-bite pressure and friction, critical chatter speed and vibration amplitude\n"
              "of a cold-rolling mill.\n"
              "\n"
              "commands:\n"
              "  scenario      print the default scenario (JSON, engineering units in every name)\n"
              "  run FILE      evaluate the request in FILE ('-' reads standard input) and print\n"
              "                the result, or RFC 9457 problem details if the request is invalid;\n"
              "                --format csv prints a table of the result as CSV instead\n"
              "                (--table NAME picks which: distribution, scan, points, ...)\n"
              "  serve         run the HTTP service (REST API v1; 'rollgap serve --help')\n"
              "  healthcheck   ask a running service's /readyz (container health check)\n"
              "  openapi       print the service's OpenAPI 3.1 document\n"
              "  --help        print this help\n"
              "  --version     print the version\n"
              "\n"
              "A request is {\"analysis\": NAME, \"scenario\": {...}, \"options\": {...}}; its\n"
              "scenario is a JSON merge patch (RFC 7396) onto the default scenario.\n"
              "analyses:\n";
    std::size_t name_width = 12;  // the command column above
    for (const Analysis& analysis : analyses()) name_width = std::max(name_width, analysis.name.size());
    for (const Analysis& analysis : analyses()) {
        stream << "  " << analysis.name << std::string(name_width + 2 - analysis.name.size(), ' ')
               << analysis.summary << '\n';
    }
    stream << "\n"
              "exit status: 0 success, 1 internal error, 2 invalid request or usage\n";
}

int usage_error(std::ostream& err, std::string_view message) {
    err << "rollgap: " << message << "\n\n";
    print_usage(err);
    return exit_bad_input;
}

void print_json(std::ostream& out, const nlohmann::json& document) {
    // Client strings echoed in messages are valid UTF-8 when parsed from text, but a JSON
    // built in code need not be: replace, never throw while reporting.
    out << document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << '\n';
}

// Reads at most max_request_bytes + 1 bytes: enough for evaluate_text to refuse an oversized
// request without reading all of it.
std::optional<std::string> read_bounded(std::istream& stream) {
    std::string text;
    std::array<char, 64 * 1024> buffer{};
    while (text.size() <= max_request_bytes && stream) {
        stream.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
        text.append(buffer.data(), static_cast<std::size_t>(stream.gcount()));
    }
    if (stream.bad()) return std::nullopt;
    return text;
}

int exit_status(const Outcome& outcome) {
    if (outcome.ok()) return exit_success;
    return outcome.http_status >= 500 ? exit_internal_error : exit_bad_input;
}

int print_outcome(std::ostream& out, const Outcome& outcome) {
    print_json(out, outcome.body);
    return exit_status(outcome);
}

int run_request(std::string_view source, std::istream& in, std::ostream& out, bool csv, std::string_view table) {
    std::optional<std::string> text;
    if (source == "-") {
        text = read_bounded(in);
    } else {
        std::ifstream file{std::string(source), std::ios::binary};
        if (file) text = read_bounded(file);
    }
    if (!text) {
        const std::string name = source == "-" ? std::string("standard input") : api::concat("'", source, "'");
        return print_outcome(out, problem_outcome(api::make_problem(api::ProblemCode::unreadable_input,
                                                                    api::concat("cannot read ", name))));
    }
    const Outcome outcome = evaluate_text(*text);
    if (!csv || !outcome.ok()) return print_outcome(out, outcome);
    const CsvAnswer answer = csv_answer(outcome.body, table);
    if (answer.status != 200) {
        out << answer.body << '\n';
        return exit_bad_input;
    }
    out << answer.body;
    return exit_success;
}

}  // namespace

int run_cli(std::span<const std::string_view> arguments, std::istream& in, std::ostream& out,
            std::ostream& err) {
    if (arguments.empty()) return usage_error(err, "a command is required");
    const std::string_view command = arguments.front();
    const auto operands = arguments.subspan(1);

    if (command == "--help" || command == "-h" || command == "help") {
        print_usage(out);
        return exit_success;
    }
    if (command == "--version") {
        out << "rollgap " << version() << '\n';
        return exit_success;
    }
    if (command == "scenario") {
        if (!operands.empty()) return usage_error(err, "'scenario' takes no arguments");
        print_json(out, api::default_scenario_json());
        return exit_success;
    }
    if (command == "run") {
        // run FILE [--format json|csv] [--table NAME]
        std::string_view format = "json", table, source;
        for (std::size_t i = 0; i < operands.size(); ++i) {
            const bool valued = (operands[i] == "--format" || operands[i] == "--table") && i + 1 < operands.size();
            if (valued) {
                std::string_view& target = operands[i] == "--format" ? format : table;
                target = operands[++i];
            } else if (source.empty() && !operands[i].starts_with("--")) {
                source = operands[i];
            } else {
                return usage_error(err, api::concat("'run': unexpected '", operands[i], "'"));
            }
        }
        if (source.empty()) return usage_error(err, "'run' takes one argument: FILE or '-'");
        if (format != "json" && format != "csv") return usage_error(err, "'run --format' is json or csv");
        return run_request(source, in, out, format == "csv", table);
    }
    return usage_error(err, api::concat("unknown command '", command, "'"));
}

}  // namespace rollgap::service
