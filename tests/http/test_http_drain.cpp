// The drain on shutdown: every request that was read gets a complete answer (its own status,
// or 503 problem when the drain stopped it), no new synchronous work is accepted while
// draining, and shutdown() returns within the drain timeout plus a small margin whatever the
// clients do (a client that sends one byte at a time cannot hold it).

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

// The margin docs/operations.md documents past the drain timeout ("Logs, metrics, health,
// shutdown").
constexpr milliseconds documented_drain_margin{2000};

}  // namespace

TEST_CASE(
    "drain: running and queued requests all get a 503 problem at the drain timeout, none waits for its deadline") {
    Gate gate;  // never opened: each computation runs until cancelled
    service::ServerConfig config = test_config();
    config.workers = 1;
    config.queue_length = 8;
    config.deadline = milliseconds(20000);
    config.drain_timeout = milliseconds(300);
    TestServer server(config, gate.evaluator());
    constexpr int requests = 4;  // one running, three queued
    std::vector<int> statuses(requests, 0);
    std::vector<std::string> codes(requests);
    std::vector<std::unique_ptr<Background>> clients;
    for (int i = 0; i < requests; ++i) {
        clients.push_back(std::make_unique<Background>([&, i] {
            auto client = server.client();
            const auto result = post_json(client, "/v1/roll-gap", json::object());
            statuses[i] = result ? result->status : -1;
            if (result && !result->body.empty())
                codes[i] = json::parse(result->body).value("code", "");
        }));
    }
    REQUIRE(eventually([&] {
        return gate.started() == 1 && server.server->pool_stats().interactive_queued == 3;
    }));

    const auto start = SteadyClock::now();
    server.server->shutdown();
    for (auto& client : clients) client->join();
    const auto elapsed = SteadyClock::now() - start;
    CHECK(elapsed < config.drain_timeout + documented_drain_margin);
    for (int i = 0; i < requests; ++i) {
        CAPTURE(i);
        CHECK(statuses[i] == 503);
        CHECK(codes[i] == "overloaded");
    }
    CHECK(gate.started() == 1);  // the queued ones were answered without running
}

TEST_CASE("drain: a new synchronous request while draining gets 503 at once") {
    Gate gate;
    service::ServerConfig config = test_config();
    config.drain_timeout = milliseconds(5000);
    TestServer server(config, gate.evaluator());
    Background in_flight([&] {
        auto client = server.client();
        post_json(client, "/v1/roll-gap", json::object());
    });
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    Background stopping([&] { server.server->shutdown(); });
    REQUIRE(eventually([&] { return server.server->draining(); }));

    auto client = server.client();
    const auto result = post_json(client, "/v1/roll-gap", json::object());
    REQUIRE(result);
    CHECK(result->status == 503);
    CHECK(result->get_header_value("Retry-After") == "1");
    CHECK(json::parse(result->body)["code"] == "overloaded");
    CHECK(gate.started() == 1);  // it was not queued
    gate.open();
}

TEST_CASE("drain: a client sending one byte at a time does not hold the shutdown") {
    service::ServerConfig config = test_config();
    config.drain_timeout = milliseconds(200);
    TestServer server(config);
    std::atomic<bool> stop_sending{false};
    RawConnection slow(server.port());
    Background sender([&] {
        const std::string request =
            "GET /livez HTTP/1.1\r\nHost: x\r\nX-Slow: " + std::string(400, 'a') + "\r\n\r\n";
        for (std::size_t i = 0; i < request.size() && !stop_sending; ++i) {
            if (!slow.send(request.substr(i, 1))) break;
            std::this_thread::sleep_for(milliseconds(100));
        }
    });
    std::this_thread::sleep_for(milliseconds(300));  // the request has begun
    const auto start = SteadyClock::now();
    server.server->shutdown();
    const auto elapsed = SteadyClock::now() - start;
    stop_sending = true;
    sender.join();
    CHECK(elapsed < config.drain_timeout + documented_drain_margin);
    CHECK_FALSE(server.server->running());
}
