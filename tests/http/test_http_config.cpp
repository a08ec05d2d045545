// Configuration of `rollgap serve` (service/config.h): flags over environment over defaults,
// errors for bad values, the token from the environment or a file and never in a message.

#include "service/config.h"

#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <unistd.h>
#include <variant>
#include <vector>

using namespace rollgap::service;

namespace {

// The process environment for one parse: every variable of the settings table unset, then
// `values` set; the previous values come back at the end of the scope. CLI11 reads the
// variables with getenv, and the tests run one at a time.
class ScopedEnvironment {
public:
    explicit ScopedEnvironment(const std::map<std::string, std::string>& values) {
        for (const ConfigSetting& setting : config_settings()) {
            const std::string name(setting.env);
            const char* previous = std::getenv(name.c_str());
            saved_.emplace_back(name,
                                previous ? std::optional<std::string>(previous) : std::nullopt);
            ::unsetenv(name.c_str());
        }
        for (const auto& [name, value] : values) ::setenv(name.c_str(), value.c_str(), 1);
    }
    ~ScopedEnvironment() {
        for (const auto& [name, value] : saved_) {
            if (value) {
                ::setenv(name.c_str(), value->c_str(), 1);
            } else {
                ::unsetenv(name.c_str());
            }
        }
    }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

std::variant<ServerConfig, ConfigHelp, std::string> parse(
    std::vector<std::string_view> arguments, const std::map<std::string, std::string>& env = {}) {
    const ScopedEnvironment scope(env);
    return parse_server_config(arguments);
}

}  // namespace

TEST_CASE("serve config: defaults") {
    const auto parsed = parse({});
    REQUIRE(std::holds_alternative<ServerConfig>(parsed));
    const ServerConfig config = std::get<ServerConfig>(parsed);
    CHECK(config.bind_address == "127.0.0.1");
    CHECK(config.port == 8080);
    CHECK(config.deadline == std::chrono::seconds(30));
    CHECK(config.max_body_bytes == 1024 * 1024);
    CHECK_FALSE(config.token);
    const ServerConfig resolved = config.resolved();
    CHECK(resolved.workers >= 1);
    CHECK(resolved.job_workers >= 1);
    CHECK(resolved.job_workers <= resolved.workers);
    CHECK_FALSE(resolved.instance.empty());
}

TEST_CASE(
    "serve config: the defaults keep the README's capacity rule, workers + queue-length < io-threads") {
    // Overload shows as fast 503s only if a connection thread is left to answer them while every
    // worker is busy and the queue is full. The default workers are the machine's cores: the
    // rule must hold on this machine and on any machine with up to 63 cores.
    const auto parsed = parse({});
    REQUIRE(std::holds_alternative<ServerConfig>(parsed));
    const ServerConfig config = std::get<ServerConfig>(parsed);
    const ServerConfig resolved = config.resolved();
    CHECK(resolved.workers + resolved.queue_length < resolved.io_threads);
    CHECK(63 + config.queue_length < config.io_threads);
}

TEST_CASE("serve config: environment, then flags (both --flag value and --flag=value)") {
    const auto parsed = parse({"--port", "9000", "--workers=3", "--deadline-ms", "1500"},
                              {{"ROLLGAP_PORT", "7000"},
                               {"ROLLGAP_BIND", "0.0.0.0"},
                               {"ROLLGAP_QUEUE_LENGTH", "5"},
                               {"ROLLGAP_LOG_LEVEL", "warn"},
                               {"ROLLGAP_JOB_RETENTION_MS", "1000"},
                               {"ROLLGAP_ANALYSIS_THREADS", "1"}});
    REQUIRE(std::holds_alternative<ServerConfig>(parsed));
    const ServerConfig config = std::get<ServerConfig>(parsed);
    CHECK(config.port == 9000);  // the flag wins
    CHECK(config.bind_address == "0.0.0.0");
    CHECK(config.workers == 3);
    CHECK(config.queue_length == 5);
    CHECK(config.deadline == std::chrono::milliseconds(1500));
    CHECK(config.log_level == "warn");
    CHECK(config.job_retention == std::chrono::seconds(1));
    CHECK(config.analysis_threads == 1);
}

TEST_CASE("serve config: bad values and unknown options are errors naming the option") {
    for (const auto& [arguments, expected] :
         std::vector<std::pair<std::vector<std::string_view>, std::string>>{
             {{"--port", "70000"}, "--port"},
             {{"--workers", "many"}, "--workers"},
             {{"--log-level", "loud"}, "--log-level"},
             {{"--deadline-ms", "0"}, "--deadline-ms"},
             {{"--analysis-threads", "-2"}, "--analysis-threads"},
             {{"--prot", "80"}, "unknown option '--prot'; did you mean '--port'?"},
             {{"--port=70000"}, "--port"},
             {{"--port"}, "--port"},
         }) {
        const auto parsed = parse(arguments);
        REQUIRE(std::holds_alternative<std::string>(parsed));
        CHECK(std::get<std::string>(parsed).find(expected) != std::string::npos);
    }
    const auto from_env = parse({}, {{"ROLLGAP_MAX_JOBS", "-1"}});
    REQUIRE(std::holds_alternative<std::string>(from_env));
    CHECK(std::get<std::string>(from_env).find("ROLLGAP_MAX_JOBS") != std::string::npos);
    // A flag replaces its variable: a bad value there is not read at all.
    const auto overridden = parse({"--max-jobs", "5"}, {{"ROLLGAP_MAX_JOBS", "-1"}});
    REQUIRE(std::holds_alternative<ServerConfig>(overridden));
    CHECK(std::get<ServerConfig>(overridden).max_jobs == 5);
    CHECK(std::holds_alternative<ConfigHelp>(parse({"--help"})));
}

TEST_CASE("serve config: the token comes from the environment or a file and is never printed") {
    const std::string secret = "s3cret-t0ken-value";
    const auto from_env = parse({}, {{"ROLLGAP_TOKEN", secret}});
    REQUIRE(std::holds_alternative<ServerConfig>(from_env));
    CHECK(std::get<ServerConfig>(from_env).token == secret);
    CHECK(describe(std::get<ServerConfig>(from_env)).find(secret) == std::string::npos);
    CHECK(describe(std::get<ServerConfig>(from_env)).find("token=set") != std::string::npos);

    const auto path =
        std::filesystem::temp_directory_path() / ("rollgap-token-" + std::to_string(::getpid()));
    std::ofstream(path) << "file-token\n";
    const auto from_file = parse({"--token-file", path.string()}, {{"ROLLGAP_TOKEN", secret}});
    std::filesystem::remove(path);
    REQUIRE(std::holds_alternative<ServerConfig>(from_file));
    CHECK(std::get<ServerConfig>(from_file).token == "file-token");  // trailing newline dropped

    const auto empty = parse({}, {{"ROLLGAP_TOKEN", ""}});
    REQUIRE(std::holds_alternative<std::string>(empty));
    // There is no --token flag: a secret on the command line would show in ps.
    CHECK(std::holds_alternative<std::string>(parse({"--token", secret})));
    CHECK(std::get<std::string>(parse({"--token", secret})).find(secret) == std::string::npos);
    const std::string inline_secret = "--token=" + secret;
    REQUIRE(std::holds_alternative<std::string>(parse({inline_secret})));
    CHECK(std::get<std::string>(parse({inline_secret})).find(secret) == std::string::npos);
}

TEST_CASE("serve config: callbacks need allowed prefixes and a secret file, never printed") {
    const std::string secret = "whsec-0123456789abcdef";
    const auto path =
        std::filesystem::temp_directory_path() / ("rollgap-whsec-" + std::to_string(::getpid()));
    std::ofstream(path) << secret << "\n";
    const auto parsed =
        parse({"--webhook-allow", "https://mes.plant.example/hooks, http://10.0.0.7:8088/",
               "--webhook-secret-file", path.string(), "--webhook-backoff-ms", "250",
               "--webhook-max-attempts", "3"});
    REQUIRE(std::holds_alternative<ServerConfig>(parsed));
    const ServerConfig config = std::get<ServerConfig>(parsed);
    REQUIRE(config.webhook_allow.size() == 2);
    CHECK(config.webhook_allow[0].host == "mes.plant.example");
    CHECK(config.webhook_allow[0].port == 443);
    CHECK(config.webhook_allow[1].port == 8088);
    CHECK(config.webhook_secret == secret);  // trailing newline dropped
    CHECK(config.webhook_backoff == std::chrono::milliseconds(250));
    CHECK(config.webhook_max_attempts == 3);
    CHECK(describe(config).find(secret) == std::string::npos);
    CHECK(describe(config).find("webhook_secret=set") != std::string::npos);

    // prefixes without a secret: callbacks are always signed
    const auto unsigned_ = parse({"--webhook-allow", "https://mes.plant.example/hooks"});
    REQUIRE(std::holds_alternative<std::string>(unsigned_));
    CHECK(std::get<std::string>(unsigned_).find("--webhook-secret-file") != std::string::npos);
    for (const char* bad : {"mes.plant.example/hooks", "https://user@mes/hooks",
                            "https://mes/hooks?x=1", "ftp://mes/hooks"}) {
        CAPTURE(bad);
        const auto refused =
            parse({"--webhook-allow", bad, "--webhook-secret-file", path.string()});
        REQUIRE(std::holds_alternative<std::string>(refused));
        CHECK(std::get<std::string>(refused).find("--webhook-allow") != std::string::npos);
    }
    std::ofstream(path) << "short\n";
    const auto weak = parse({"--webhook-secret-file", path.string()});
    std::filesystem::remove(path);
    REQUIRE(std::holds_alternative<std::string>(weak));
    CHECK(std::get<std::string>(weak).find("at least 16") != std::string::npos);
    CHECK(std::get<std::string>(weak).find("short") == std::string::npos);
    // no prefixes: no callbacks, and no secret needed
    CHECK(std::get<ServerConfig>(parse({})).webhook_allow.empty());
}

TEST_CASE("serve config: --help lists every setting with its environment variable") {
    const std::string usage = config_usage();
    for (const ConfigSetting& setting : config_settings()) {
        CAPTURE(setting.env);
        CHECK(usage.find(setting.env) != std::string::npos);
        if (!setting.flag.empty()) CHECK(usage.find(setting.flag) != std::string::npos);
    }
}

TEST_CASE(
    "serve config: the admin listener's port is 8081 unless set, with --port 0 it is any free port too") {
    const auto resolved = [](std::vector<std::string_view> arguments) {
        const auto parsed = parse(std::move(arguments));
        REQUIRE(std::holds_alternative<ServerConfig>(parsed));
        return std::get<ServerConfig>(parsed).resolved();
    };
    CHECK(resolved({}).admin_port == 8081);
    CHECK(resolved({}).admin_bind_address == "127.0.0.1");
    CHECK(resolved({"--port", "0"}).admin_port == 0);
    CHECK(resolved({"--port", "0", "--admin-port", "9091"}).admin_port == 9091);
    CHECK(resolved({"--admin-port", "0", "--admin-bind", "0.0.0.0"}).admin_bind_address ==
          "0.0.0.0");
}
