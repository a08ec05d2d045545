// The admin listener (/livez, /readyz, /metrics on threads of their own) and the total read
// deadline of the public listener: clients that send one byte at a time hold every public
// connection thread only until the deadline, and health answers on the admin port throughout.

#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;
using std::chrono::milliseconds;
using SteadyClock = std::chrono::steady_clock;

namespace {

httplib::Client admin_client(const TestServer& server, int read_timeout_ms = 1000) {
    httplib::Client client("127.0.0.1", server.server->admin_port());
    client.set_connection_timeout(0, 500'000);
    client.set_read_timeout(0, read_timeout_ms * 1000);
    return client;
}

}  // namespace

TEST_CASE("admin: /livez, /readyz and /metrics on the admin port, nothing else there") {
    TestServer server;
    REQUIRE(server.server->admin_port() > 0);
    CHECK(server.server->admin_port() != server.port());
    auto client = admin_client(server);
    const auto live = client.Get("/livez");
    REQUIRE(live);
    CHECK(live->status == 200);
    CHECK(json::parse(live->body)["status"] == "alive");
    const auto ready = client.Get("/readyz");
    REQUIRE(ready);
    CHECK(ready->status == 200);
    const auto metrics = client.Get("/metrics");
    REQUIRE(metrics);
    CHECK(metrics->status == 200);
    CHECK(metrics->body.find("rollgap_ready 1") != std::string::npos);

    const auto compute = client.Post("/v1/roll-gap", "{}", "application/json");
    REQUIRE(compute);
    CHECK(compute->status == 404);
    CHECK(json::parse(compute->body)["code"] == "not_found");
    const auto openapi = client.Get("/openapi.json");
    REQUIRE(openapi);
    CHECK(openapi->status == 404);
}

TEST_CASE(
    "admin: slow clients on every public connection thread are cut off at the read deadline, "
    "/livez answers on the admin port throughout") {
    service::ServerConfig config = test_config();
    config.io_threads = 2;
    config.read_deadline = milliseconds(1500);
    TestServer server(config);

    constexpr int slow_clients = 2;  // one per public connection thread
    std::vector<std::unique_ptr<RawConnection>> connections;
    for (int i = 0; i < slow_clients; ++i)
        connections.push_back(std::make_unique<RawConnection>(server.port()));
    std::vector<SteadyClock::duration> held(slow_clients);
    std::vector<std::string> answers(slow_clients);
    std::vector<std::unique_ptr<Background>> senders;
    const auto start = SteadyClock::now();
    for (int i = 0; i < slow_clients; ++i) {
        senders.push_back(std::make_unique<Background>([&, i] {
            // One header byte every 400 ms, for at most 12 s: never a whole request.
            const std::string request =
                "GET /livez HTTP/1.1\r\nHost: x\r\nX-Slow: " + std::string(60, 'a');
            for (char byte : request) {
                if (!connections[i]->send(std::string(1, byte))) break;
                if (connections[i]->closed_by_server(milliseconds(400))) break;
            }
            held[i] = SteadyClock::now() - start;
            answers[i] = connections[i]->received();
        }));
    }

    // Health on the admin port, every 100 ms while the slow clients hold the public threads.
    int probes = 0, healthy = 0;
    while (SteadyClock::now() - start < milliseconds(2500)) {
        auto client = admin_client(server);
        const auto live = client.Get("/livez");
        ++probes;
        if (live && live->status == 200) ++healthy;
        std::this_thread::sleep_for(milliseconds(100));
    }
    for (auto& sender : senders) sender->join();
    CHECK(probes >= 10);
    CHECK(healthy == probes);
    for (int i = 0; i < slow_clients; ++i) {
        CAPTURE(i);
        CAPTURE(answers[i]);
        CHECK(held[i] < config.read_deadline + milliseconds(1000));
        CHECK(raw_status(answers[i]) == 408);
        CHECK(json::parse(raw_body(answers[i]))["code"] == "request_timeout");
    }
    // The public threads are free again.
    auto client = server.client(2);
    const auto live = client.Get("/livez");
    REQUIRE(live);
    CHECK(live->status == 200);
}

TEST_CASE("admin: /readyz on the admin port fails as soon as the drain starts") {
    Gate gate;
    TestServer server(test_config(), gate.evaluator());
    Background in_flight([&] {
        auto client = server.client();
        post_json(client, "/v1/roll-gap", json::object());
    });
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    Background stopping([&] { server.server->shutdown(); });
    REQUIRE(eventually([&] { return server.server->draining(); }));
    auto client = admin_client(server);
    const auto ready = client.Get("/readyz");
    REQUIRE(ready);
    CHECK(ready->status == 503);
    const auto live = client.Get("/livez");
    REQUIRE(live);
    CHECK(live->status == 200);
    gate.open();
}
