// Secrets and trust over HTTP (issue 16, item 4), against a real server in process: the Host
// check against DNS rebinding, refusal of cross-site browser requests, and client keys with
// scopes from a key file that is re-read without a restart.

#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "service/cli.h"
#include "service/client_keys.h"
#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;

namespace {

// The product's default: the Host check follows the bind address (test_config() serves any).
service::ServerConfig default_hosts_config() {
    service::ServerConfig config = test_config();
    config.allowed_hosts.clear();
    return config;
}

std::string get_with_host(int port, const std::string& path, const std::string& host) {
    return raw_exchange(
        port, "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\nConnection: close\r\n\r\n");
}

json problem_of(const httplib::Result& result) {
    REQUIRE(result);
    CHECK(result->get_header_value("Content-Type") == "application/problem+json");
    return json::parse(result->body);
}

void write_file(const std::string& path, const std::string& text) {
    // Written beside and renamed, as a mounted Secret is swapped: never read half-written.
    const std::string temporary = path + ".new";
    std::ofstream(temporary, std::ios::trunc) << text;
    std::filesystem::rename(temporary, path);
}

// A key made the way an operator makes one (`rollgap key new`).
service::NewKey make_key(const std::string& name, const std::string& scopes) {
    const auto key = service::new_key(name, scopes);
    REQUIRE(key);
    return *key;
}

httplib::Headers bearer(const std::string& key) { return {{"Authorization", "Bearer " + key}}; }

}  // namespace

TEST_CASE("trust: on loopback a Host outside the served names is 421 (DNS rebinding)") {
    TestServer server(default_hosts_config());
    const int port = server.port();
    const std::string p = ":" + std::to_string(port);
    // A page of evil.example whose name was rebound to 127.0.0.1.
    const std::string rebound = get_with_host(port, "/v1/scenarios/default", "evil.example" + p);
    CHECK(rebound.starts_with("HTTP/1.1 421"));
    CHECK(rebound.find("misdirected_request") != std::string::npos);
    CHECK(rebound.find("evil.example") == std::string::npos);  // the Host is not echoed
    CHECK(get_with_host(port, "/v1/roll-gap", "evil.example").starts_with("HTTP/1.1 421"));
    // The names of this machine's loopback service.
    for (const std::string& host :
         std::vector<std::string>{"127.0.0.1" + p, "localhost" + p, "LOCALHOST", "[::1]" + p}) {
        CAPTURE(host);
        CHECK(get_with_host(port, "/v1/scenarios/default", host).starts_with("HTTP/1.1 200"));
    }
    // The admin listener is never checked (probes use any name).
    CHECK(get_with_host(server.server->admin_port(), "/livez", "evil.example")
              .starts_with("HTTP/1.1 200"));

    // --allowed-hosts replaces the default.
    service::ServerConfig named = default_hosts_config();
    named.allowed_hosts = {"rollgap.example"};
    TestServer proxied(named);
    CHECK(get_with_host(proxied.port(), "/v1/scenarios/default", "rollgap.example:443")
              .starts_with("HTTP/1.1 200"));
    CHECK(get_with_host(proxied.port(), "/v1/scenarios/default", "127.0.0.1")
              .starts_with("HTTP/1.1 421"));

    // Bound to every interface, without --allowed-hosts: no check (the operator chose a
    // network); bound to loopback: the default names.
    service::ServerConfig open = default_hosts_config();
    open.bind_address = "0.0.0.0";
    CHECK(open.resolved().allowed_hosts.empty());
    CHECK(default_hosts_config().resolved().allowed_hosts ==
          std::vector<std::string>{"127.0.0.1", "localhost", "127.0.0.1", "::1"});
}

TEST_CASE("trust: unsafe requests from a foreign browser page are 403, curl without a body works") {
    service::ServerConfig config = default_hosts_config();
    config.allowed_origins = {"https://app.example"};
    TestServer server(config);
    auto client = server.client();
    const std::string own = "http://127.0.0.1:" + std::to_string(server.port());

    // `curl -X POST http://127.0.0.1:8080/v1/roll-gap`: no body, no type, no Origin.
    CHECK(client.Post("/v1/roll-gap")->status == 200);
    // A form on another site posting an empty text/plain body (no preflight in a browser).
    const auto forged =
        client.Post("/v1/roll-gap", {{"Origin", "http://evil.example"}}, "", "text/plain");
    REQUIRE(forged);
    CHECK(forged->status == 403);
    CHECK(problem_of(forged)["code"] == "cross_site_request");
    CHECK(client.Post("/v1/roll-gap", {{"Origin", "null"}}, "", "text/plain")->status == 403);
    for (const std::string site : {"cross-site", "same-site"}) {
        CAPTURE(site);
        CHECK(client.Post("/v1/roll-gap", {{"Sec-Fetch-Site", site}}, "", "text/plain")->status ==
              403);
    }
    // The service's own page (the workbench at /) and the allowed origin.
    CHECK(client
              .Post("/v1/roll-gap", {{"Origin", own}, {"Sec-Fetch-Site", "same-origin"}}, "{}",
                    "application/json")
              ->status == 200);
    CHECK(client
              .Post("/v1/roll-gap",
                    {{"Origin", "https://app.example"}, {"Sec-Fetch-Site", "cross-site"}}, "{}",
                    "application/json")
              ->status == 200);
    CHECK(client.Post("/v1/roll-gap", httplib::Headers{{"Sec-Fetch-Site", "none"}})->status == 200);
    // PUT and DELETE are unsafe too; a GET from anywhere is a read the browser keeps from the page.
    const httplib::Headers evil = {{"Origin", "http://evil.example"}};
    CHECK(client.Put("/v1/scenarios/stand-1", evil, "{}", "application/json")->status == 403);
    CHECK(client.Delete("/v1/scenarios/stand-1", evil)->status == 403);
    CHECK(client.Get("/v1/scenarios/default", evil)->status == 200);
}

TEST_CASE("trust: client keys with scopes, 401 without a known key, 403 naming the scope") {
    const std::string dir = fresh_temp_dir();
    const auto reader = make_key("reader", "read");
    const auto runner = make_key("ci-runner", "compute");
    const auto editor = make_key("editor", "read,write");
    const auto root = make_key("ops", "admin");
    write_file(dir + "/keys", "# name sha256 scopes\n" + reader.line + "\n" + runner.line + "\n" +
                                  editor.line + "\n\n" + root.line + "\n");
    service::ServerConfig config = test_config();
    config.key_file = dir + "/keys";
    TestServer server(config);
    auto client = server.client();

    CHECK(client.Get("/v1/scenarios")->status == 401);
    CHECK(client.Get("/v1/scenarios", bearer("rg_reader_" + std::string(64, '0')))->status == 401);
    CHECK(client.Get("/v1/scenarios", bearer("rg_nobody_00"))->status == 401);
    CHECK(client.Get("/v1/scenarios", bearer("not-a-key"))->status == 401);

    CHECK(client.Get("/v1/scenarios", bearer(reader.key))->status == 200);
    CHECK(client.Get("/v1/jobs", bearer(reader.key))->status == 200);
    const auto no_compute =
        client.Post("/v1/roll-gap", bearer(reader.key), "{}", "application/json");
    REQUIRE(no_compute);
    CHECK(no_compute->status == 403);
    const json problem = problem_of(no_compute);
    CHECK(problem["code"] == "forbidden");
    CHECK(problem["detail"].get<std::string>().find("reader lacks the scope compute") !=
          std::string::npos);
    CHECK(no_compute->get_header_value("WWW-Authenticate").find("scope=\"compute\"") !=
          std::string::npos);
    const auto no_write =
        client.Put("/v1/scenarios/stand-1", bearer(reader.key), "{}", "application/json");
    CHECK(no_write->status == 403);
    CHECK(problem_of(no_write)["detail"].get<std::string>().find("scope write") !=
          std::string::npos);

    CHECK(client.Post("/v1/roll-gap", bearer(runner.key), "{}", "application/json")->status == 200);
    CHECK(client.Get("/v1/jobs", bearer(runner.key))->status == 403);
    CHECK(problem_of(client.Get("/v1/jobs", bearer(runner.key)))["detail"].get<std::string>().find(
              "scope read") != std::string::npos);

    // The author of every stored version is the key's name.
    CHECK(
        client.Put("/v1/scenarios/stand-1", bearer(editor.key), "{}", "application/json")->status ==
        201);
    const auto stored = client.Get("/v1/scenarios/stand-1", bearer(editor.key));
    REQUIRE(stored);
    CHECK(stored->get_header_value("Rollgap-Author") == "editor");
    CHECK(body_json(client.Get("/v1/scenarios", bearer(reader.key)))["scenarios"][0]["author"] ==
          "editor");
    CHECK(client.Delete("/v1/scenarios/stand-1", bearer(editor.key))->status == 204);
    CHECK(client.Post("/v1/roll-gap", bearer(editor.key), "{}", "application/json")->status == 403);

    // admin holds every scope.
    CHECK(client.Post("/v1/roll-gap", bearer(root.key), "{}", "application/json")->status == 200);
    CHECK(client.Put("/v1/scenarios/stand-2", bearer(root.key), "{}", "application/json")->status ==
          201);

    // Health, metrics, the default scenario and the OpenAPI document stay keyless.
    CHECK(client.Get("/livez")->status == 200);
    CHECK(client.Get("/v1/scenarios/default")->status == 200);
    CHECK(client.Get("/openapi.json")->status == 200);

    // The request log names the key, never the key itself.
    const std::string log = server.log_text();
    CHECK(log.find("key=reader") != std::string::npos);
    CHECK(log.find("key=ci-runner") != std::string::npos);
    CHECK(log.find("key=editor") != std::string::npos);
    CHECK(log.find("key=anonymous") != std::string::npos);
    for (const auto* key : {&reader, &runner, &editor, &root})
        CHECK(log.find(key->key.substr(key->key.rfind('_') + 1)) == std::string::npos);
}

TEST_CASE("trust: the key file is re-read without a restart, a broken one keeps the last keys") {
    const std::string dir = fresh_temp_dir();
    const std::string path = dir + "/keys";
    const auto old_key = make_key("old", "read");
    const auto new_key = make_key("new", "read");
    write_file(path, old_key.line + "\n");
    service::ServerConfig config = test_config();
    config.key_file = path;
    TestServer server(config);
    auto client = server.client();
    const auto status_with = [&](const service::NewKey& key) {
        return client.Get("/v1/scenarios", bearer(key.key))->status;
    };
    CHECK(status_with(old_key) == 200);
    CHECK(status_with(new_key) == 401);

    // Rotation: the new key replaces the old one, within about a second (checked every second).
    write_file(path, new_key.line + "\n");
    const auto rotated_at = std::chrono::steady_clock::now();
    CHECK(eventually([&] { return status_with(new_key) == 200; }, std::chrono::seconds(3)));
    CHECK(std::chrono::steady_clock::now() - rotated_at < std::chrono::milliseconds(2500));
    CHECK(status_with(old_key) == 401);

    // A broken file (a bad line) is not taken: the last good keys stay, and it is logged once
    // (by the process logger), naming the line but not its text.
    const auto sink = std::make_shared<CapturingSink>();
    const auto previous = spdlog::default_logger();
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("trust-test", sink));
    write_file(path, new_key.line + "\nthis is not a key line\n");
    CHECK(eventually(
        [&] {
            return status_with(new_key) == 200 &&
                   sink->text().find("not reloaded") != std::string::npos;
        },
        std::chrono::seconds(3)));
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    CHECK(status_with(new_key) == 200);
    spdlog::set_default_logger(previous);
    const std::string warnings = sink->text();
    CHECK(warnings.find("line 2") != std::string::npos);
    CHECK(warnings.find("this is not") == std::string::npos);
    CHECK(warnings.find("not reloaded") == warnings.rfind("not reloaded"));  // once

    // A key file that cannot be read at start is a start failure, naming the file only.
    service::ServerConfig missing = test_config();
    missing.key_file = dir + "/absent";
    service::HttpServer refused(missing);
    std::string error;
    CHECK_FALSE(refused.start(&error));
    CHECK(error.find("absent") != std::string::npos);
}

TEST_CASE("trust: the bearer token is a key named token with every scope") {
    service::ServerConfig config = test_config();
    config.token = "s3cret-token";
    TestServer server(config);
    auto client = server.client();
    const httplib::Headers token = bearer("s3cret-token");
    CHECK(client.Get("/v1/scenarios")->status == 401);
    CHECK(client.Get("/v1/scenarios", token)->status == 200);
    CHECK(client.Post("/v1/roll-gap", token, "{}", "application/json")->status == 200);
    CHECK(client.Put("/v1/scenarios/stand-1", token, "{}", "application/json")->status == 201);
    CHECK(client.Get("/v1/scenarios/stand-1", token)->get_header_value("Rollgap-Author") ==
          "token");
    CHECK(server.log_text().find("key=token") != std::string::npos);
    CHECK(server.log_text().find("s3cret-token") == std::string::npos);
}

TEST_CASE("trust: rollgap key new prints the key once and its key-file line") {
    std::istringstream in;
    std::ostringstream out, err;
    const std::vector<std::string_view> arguments{"key", "new", "ci", "--scopes", "read,compute"};
    REQUIRE(service::run_cli(arguments, in, out, err) == 0);
    std::istringstream lines(out.str());
    std::string key, line;
    std::getline(lines, key);
    std::getline(lines, line);
    REQUIRE(key.starts_with("rg_ci_"));
    const std::string secret = key.substr(6);
    CHECK(secret.size() == 64);
    CHECK(line == "ci " + service::sha256_hex(secret) + " read,compute");
    CHECK(line.find(secret) == std::string::npos);
    std::string parse_error;
    const auto parsed = service::parse_key_file(line + "\n", parse_error);
    REQUIRE(parsed);
    CHECK(parsed->at(0).scopes == (service::scope_read | service::scope_compute));

    std::ostringstream bad_out, bad_err;
    CHECK(service::run_cli(std::vector<std::string_view>{"key", "new", "ci", "--scopes", "root"},
                           in, bad_out, bad_err) != 0);
    CHECK(service::run_cli(
              std::vector<std::string_view>{"key", "new", "Bad_Name", "--scopes", "read"}, in,
              bad_out, bad_err) != 0);
    CHECK(bad_out.str().empty());
    // SHA-256 itself (FIPS 180-2 test vector).
    CHECK(service::sha256_hex("abc") ==
          "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}
