// Scale-out: two service instances behind nginx on loopback, a sweep sent through the proxy,
// requests spread over both instances, and a job polled through the proxy with affinity by
// client address: each instance here has a job store of its own. With a shared store
// (PostgreSQL) no affinity is needed (docs/operations.md: "Scaling out").

#include "service/analyses/table.h"

#include <doctest/doctest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <unistd.h>

#include "support/http_test.h"
#include "support/nginx.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace {

// The scale-out configuration: `upstream_servers` behind one loopback port, optionally with
// affinity by client address.
std::string scale_out_config(const std::filesystem::path& directory, int port,
                             const std::string& upstream_servers, bool affinity) {
    std::ostringstream conf;
    if (::geteuid() == 0)
        conf << "user root;\n";  // else workers run as nobody and cannot write dir
    conf
        << "worker_processes 1;\ndaemon off;\npid nginx.pid;\nerror_log " << directory.string()
        << "/error.log warn;\nevents { worker_connections 128; }\nhttp {\n  access_log off;\n"
        << "  client_body_temp_path body;\n  proxy_temp_path proxy;\n"
        << "  fastcgi_temp_path fastcgi;\n  uwsgi_temp_path uwsgi;\n  scgi_temp_path scgi;\n"
        << "  upstream rollgap {\n"
        << (affinity ? "    hash $remote_addr consistent;\n" : "") << upstream_servers
        << "    keepalive 8;\n  }\n"
        << "  server {\n    listen 127.0.0.1:" << port << ";\n    client_max_body_size 1m;\n"
        << "    location / {\n      proxy_pass http://rollgap;\n      proxy_http_version 1.1;\n"
        << "      proxy_set_header Connection \"\";\n      proxy_read_timeout 60s;\n    }\n  }\n}\n";
    return conf.str();
}

service::ServerConfig instance(const char* name) {
    service::ServerConfig config = test_config();
    config.instance = name;
    return config;
}

}  // namespace

TEST_CASE("scale-out: two instances behind nginx serve a sweep and share the load") {
    if (!nginx_installed()) {
        MESSAGE(
            "nginx is not installed (scripts/install-deps.sh installs it): scale-out test skipped");
        return;
    }
    TestServer a(instance("a"));
    TestServer b(instance("b"));
    const int port = free_loopback_port();
    REQUIRE(port > 0);
    const std::string upstream = "    server 127.0.0.1:" + std::to_string(a.port()) +
                                 ";\n    server 127.0.0.1:" + std::to_string(b.port()) + ";\n";
    const auto directory =
        std::filesystem::temp_directory_path() / ("rollgap-nginx-" + std::to_string(::getpid()));
    Nginx nginx(directory, scale_out_config(directory, port, upstream, false));

    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(0, 200'000);
    client.set_read_timeout(30, 0);
    const bool up = eventually([&] {
        const auto result = client.Get("/readyz");
        return result && result->status == 200;
    });
    CAPTURE(nginx.error_log());
    REQUIRE(up);

    if (service::find_analysis(service::analyses(), "sweep") != nullptr) {
        const json sweep = {
            {"options",
             {{"parameter", "/lubricant/viscosity_Pa_s"},
              {"values", {0.0004, 0.00055, 0.0007}},
              {"critical_speed", {{"speed_min_m_per_s", 10}, {"speed_max_m_per_s", 40}}}}}};
        const auto result = post_json(client, "/v1/sweeps", sweep);
        REQUIRE(result);
        CAPTURE(result->body.substr(0, 300));
        CHECK(result->status == 200);
        const json answer = json::parse(result->body);
        CHECK(answer["analysis"] == "sweep");
        CHECK(answer["result"]["points"].size() == 3);
    } else {
        MESSAGE("the facade offers no sweep yet: sending roll-gap requests only");
    }

    // Round robin: both instances answer.
    for (int i = 0; i < 10; ++i) {
        const auto result =
            post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}});
        REQUIRE(result);
        CHECK(result->status == 200);
    }
    const auto served_by = [](TestServer& server) {
        return server.server->metrics().request_count("POST", "/v1/roll-gap", 200) +
               server.server->metrics().request_count("POST", "/v1/sweeps", 200);
    };
    // Counted once the answers are written.
    const std::uint64_t expected =
        10 + (service::find_analysis(service::analyses(), "sweep") ? 1 : 0);
    CHECK(eventually([&] { return served_by(a) + served_by(b) == expected; }));
    CHECK(served_by(a) > 0);
    CHECK(served_by(b) > 0);

    // Problems pass through the proxy unchanged.
    const auto invalid =
        post_json(client, "/v1/roll-gap", {{"scenario", {{"strip", {{"reduction", 5}}}}}});
    REQUIRE(invalid);
    CHECK(invalid->status == 422);
    CHECK(invalid->get_header_value("Content-Type") == "application/problem+json");
}

TEST_CASE(
    "scale-out: with affinity by client address a job is polled on the instance that holds it") {
    if (!nginx_installed()) {
        MESSAGE(
            "nginx is not installed (scripts/install-deps.sh installs it): scale-out test skipped");
        return;
    }
    TestServer a(instance("a"));
    TestServer b(instance("b"));
    const int port = free_loopback_port();
    const std::string upstream = "    server 127.0.0.1:" + std::to_string(a.port()) +
                                 ";\n    server 127.0.0.1:" + std::to_string(b.port()) + ";\n";
    const auto directory = std::filesystem::temp_directory_path() /
                           ("rollgap-nginx-affinity-" + std::to_string(::getpid()));
    Nginx nginx(directory, scale_out_config(directory, port, upstream, true));
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(0, 200'000);
    client.set_read_timeout(30, 0);
    REQUIRE(eventually([&] {
        const auto result = client.Get("/readyz");
        return result && result->status == 200;
    }));
    const auto created = post_json(
        client, "/v1/jobs", {{"analysis", "roll_gap"}, {"options", {{"distributions", false}}}});
    REQUIRE(created);
    REQUIRE(created->status == 202);
    const std::string location = created->get_header_value("Location");
    const std::string holder = json::parse(created->body)["instance"];
    for (int i = 0; i < 5; ++i) {
        const auto polled = client.Get(location.c_str());
        REQUIRE(polled);
        CHECK(polled->status == 200);
        CHECK(json::parse(polled->body)["instance"] == holder);
    }
}
