#include "service/cli.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "api/name_suggestion.h"
#include "api/scenario_json.h"
#include "api/text.h"
#include "service/analyses/table.h"
#include "service/client_keys.h"
#include "service/config.h"
#include "service/csv_answer.h"
#include "service/evaluate.h"
#include "service/openapi.h"
#include "service/scenario_explain.h"
#include "service/version.h"
#include "service/worker_pool.h"

namespace rollgap::service {
namespace {

// The commands: one row each, with the description the usage text shows.
struct Command {
    std::string_view name;
    std::string_view operands;  // as the usage shows them
    std::string_view description;
};
constexpr std::array commands{
    Command{"scenario", "[--explain]",
            "print the default scenario (JSON, engineering units in every name);\n"
            "--explain: what each field is: pointer, unit, bounds, default, description"},
    Command{"run", "FILE [--format json|csv] [--table NAME] [--units si|plant]",
            "evaluate the request in FILE ('-' reads standard input) and print\n"
            "the result, or RFC 9457 problem details if the request is invalid;\n"
            "--format csv prints a table of the result as CSV instead\n"
            "(--table NAME picks which: distribution, scan, points, ...;\n"
            "--units plant: its speeds in m/min, viscosities in mPa.s)"},
    Command{"serve", "", "run the HTTP service (REST API v1; 'rollgap serve --help')"},
    Command{"healthcheck", "", "ask a running service's /readyz (container health check)"},
    Command{"openapi", "", "print the service's OpenAPI 3.1 document"},
    Command{"key", "new NAME --scopes read,compute,write,admin",
            "make a client key: prints the key (shown once) on the first line\n"
            "and the line for the key file (--key-file) on the second"},
};

CLI::App* add_command(CLI::App& app, std::string_view name) {
    const auto row = std::find_if(commands.begin(), commands.end(),
                                  [name](const Command& command) { return command.name == name; });
    CLI::App* command = app.add_subcommand(std::string(name), std::string(row->description));
    command
        ->allow_extras();  // refused after parsing, in the program's words (unexpected_arguments)
    return command;
}

void print_usage(std::ostream& stream) {
    constexpr std::size_t command_width = 14;
    const auto column = [&](std::string_view label, std::string_view text) {
        stream << "  " << label
               << std::string(label.size() < command_width ? command_width - label.size() : 1, ' ');
        for (std::size_t start = 0; start <= text.size();) {
            const std::size_t end = std::min(text.find('\n', start), text.size());
            if (start > 0) stream << std::string(command_width + 2, ' ');
            stream << text.substr(start, end - start) << '\n';
            start = end + 1;
        }
    };
    stream << "usage: rollgap <command> [arguments]\n"
              "\n"
              "Roll-bite pressure and friction, critical chatter speed and vibration amplitude\n"
              "of a cold-rolling mill.\n"
              "\n"
              "commands:\n";
    for (const Command& command : commands) {
        column(command.operands.empty() ? std::string(command.name)
                                        : api::concat(command.name, " ", command.operands),
               command.description);
    }
    column("--help", "print this help");
    column("--version", "print the version");
    stream << "\n"
              "A request is {\"analysis\": NAME, \"scenario\": {...}, \"options\": {...}}; its\n"
              "scenario is a JSON merge patch (RFC 7396) onto the default scenario.\n"
              "analyses:\n";
    std::size_t name_width = command_width - 2;
    for (const Analysis& analysis : analyses())
        name_width = std::max(name_width, analysis.name.size());
    for (const Analysis& analysis : analyses()) {
        stream << "  " << analysis.name << std::string(name_width + 2 - analysis.name.size(), ' ')
               << analysis.summary << '\n';
    }
    stream
        << "\n"
           "exit status: 0 success, 1 internal error, 2 invalid request or usage, or `serve` could "
           "not start (a port in use)\n";
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

int run_request(std::string_view source, std::istream& in, std::ostream& out, bool csv,
                std::string_view table, std::string_view units) {
    std::optional<std::string> text;
    if (source == "-") {
        text = read_bounded(in);
    } else {
        std::ifstream file{std::string(source), std::ios::binary};
        if (file) text = read_bounded(file);
    }
    if (!text) {
        const std::string name =
            source == "-" ? std::string("standard input") : api::concat("'", source, "'");
        return print_outcome(out,
                             problem_outcome(api::make_problem(api::ProblemCode::unreadable_input,
                                                               api::concat("cannot read ", name))));
    }
    // The facade's two steps, as the HTTP server takes them: prepare (a problem is printed before
    // any pool is made), then run on this thread, its inner loops also on a pool sized by the
    // CPU quota.
    auto prepared = prepare_text(*text);
    if (auto* problem = std::get_if<Outcome>(&prepared)) return print_outcome(out, *problem);
    const auto pool = local_pool();
    core::Control control;
    control.executor = pool.get();
    const Outcome outcome = run(std::move(std::get<PreparedRequest>(prepared)), control);
    if (!csv || !outcome.ok()) return print_outcome(out, outcome);
    const CsvAnswer answer = csv_answer(outcome.body, table, units);
    if (answer.status != 200) {
        out << answer.body << '\n';
        return exit_bad_input;
    }
    out << answer.body;
    return exit_success;
}

// The admin listener answers whatever the public connections do, so the health check asks it.
std::string default_healthcheck_url() {
    const char* port = std::getenv("ROLLGAP_ADMIN_PORT");
    return "http://127.0.0.1:" + std::string(port != nullptr && *port != '\0' ? port : "8081") +
           "/readyz";
}

}  // namespace

int run_cli(std::span<const std::string_view> arguments, std::istream& in, std::ostream& out,
            std::ostream& err, const ServerCommands& server) {
    // The parsed values; the commands act on them after a successful parse.
    CLI::App app("rollgap", "rollgap");
    bool show_version = false;
    app.add_flag("--version", show_version, "print the version");
    app.require_subcommand(0, 1);
    app.allow_extras();

    CLI::App* scenario = add_command(app, "scenario");
    bool explain = false;
    scenario->add_flag("--explain", explain, "what each scenario field is");
    CLI::App* run = add_command(app, "run");
    std::string source;
    run->add_option("FILE", source, "the request, '-' for standard input")->required();
    std::string format = "json";
    std::string table;
    run->add_option("--format", format, "json (default) or csv")
        ->check(CLI::IsMember({"json", "csv"}));
    run->add_option("--table", table, "with --format csv: which table of the result");
    std::string units = "si";
    run->add_option("--units", units,
                    "with --format csv: si (default) or plant (speeds in m/min, viscosities in "
                    "mPa.s)")
        ->check(CLI::IsMember({"si", "plant"}));
    CLI::App* serve_command = add_command(app, "serve");
    ServerConfig config;
    add_server_options(*serve_command, config);
    CLI::App* health = add_command(app, "healthcheck");
    std::string url = default_healthcheck_url();
    health->add_option("--url", url, "http://HOST:PORT/PATH");
    CLI::App* openapi = add_command(app, "openapi");
    CLI::App* key = add_command(app, "key");
    key->require_subcommand(1, 1);
    CLI::App* key_new = key->add_subcommand("new", "make a client key");
    key_new->allow_extras();
    std::string key_name;
    std::string key_scopes;
    key_new->add_option("NAME", key_name, "the key's name: 1..32 of a-z 0-9 . -")->required();
    key_new->add_option("--scopes", key_scopes, "comma-separated: read, compute, write, admin")
        ->required();
    CLI::App* help = app.add_subcommand("help", "print this help")->group("");

    // CLI11 takes the arguments last first.
    std::vector<std::string> reversed(arguments.rbegin(), arguments.rend());
    try {
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        if (serve_command->parsed()) {
            out << config_usage();
        } else {
            print_usage(out);
        }
        return exit_success;
    } catch (const CLI::ParseError& error) {
        if (serve_command->parsed()) {
            err << "rollgap serve: " << error.what() << '\n';
            return exit_bad_input;
        }
        return usage_error(err, error.what());
    }

    if (serve_command->parsed()) {
        if (!app.remaining().empty()) {
            // Not echoed: it may be a secret given where an option was meant.
            err << "rollgap serve: unexpected argument (rollgap serve --help)\n";
            return exit_bad_input;
        }
        if (auto error = finish_server_config(*serve_command, config)) {
            err << "rollgap serve: " << *error << '\n';
            return exit_bad_input;
        }
        if (!server.serve) {
            err << "rollgap serve: this build has no HTTP layer\n";
            return exit_internal_error;
        }
        return server.serve(config);
    }
    if (const std::vector<std::string> extras = app.remaining(); !extras.empty()) {
        const std::string& first = extras.front();
        if (app.get_subcommands().empty()) {
            std::vector<std::string_view> names;
            for (const Command& command : commands) names.push_back(command.name);
            return usage_error(
                err, api::concat("unknown command '", first, "'", api::did_you_mean(first, names)));
        }
        return usage_error(err, api::concat("unexpected argument '", first, "'"));
    }
    for (const CLI::App* command : {scenario, run, health, openapi, key_new, help}) {
        if (command->parsed() && !command->remaining().empty()) {
            return usage_error(
                err, api::concat("unexpected argument '", command->remaining().front(), "' after '",
                                 command->get_name(), "'"));
        }
    }
    if (help->parsed()) {
        print_usage(out);
        return exit_success;
    }
    if (scenario->parsed()) {
        if (explain) {
            out << scenario_explanation();
            return exit_success;
        }
        print_json(out, api::default_scenario_json());
        return exit_success;
    }
    if (run->parsed()) return run_request(source, in, out, format == "csv", table, units);
    if (health->parsed()) {
        if (!server.healthcheck) {
            err << "rollgap healthcheck: this build has no HTTP layer\n";
            return exit_internal_error;
        }
        return server.healthcheck(url, out, err);
    }
    if (key_new->parsed()) {
        const auto made = new_key(key_name, key_scopes);
        if (!made) {
            return usage_error(err,
                               "key new: NAME is 1..32 of a-z 0-9 . - and --scopes a "
                               "comma-separated list of read, compute, write, admin");
        }
        out << made->key << '\n' << made->line << '\n';
        return exit_success;
    }
    if (openapi->parsed()) {
        out << openapi_document().dump(2) << '\n';
        return exit_success;
    }
    if (show_version) {
        out << "rollgap " << version() << '\n';
        return exit_success;
    }
    return usage_error(err, "a command is required");
}

}  // namespace rollgap::service
