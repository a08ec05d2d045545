// The HTTP service under load and at its limits: a full queue answers 503 + Retry-After at once,
// a computation past its deadline is stopped and answered 504, and shutdown drains (readiness
// fails, in-flight work finishes) — in process and for the real binary on SIGTERM.

#include "service/analyses/table.h"

#include <doctest/doctest.h>

#include <csignal>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include "support/program.h"
#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

TEST_CASE(
    "overload: one worker, a queue of one: the third concurrent request gets 503 + Retry-After at once") {
    Gate gate;
    service::ServerConfig config = test_config();
    config.workers = 1;
    config.queue_length = 1;
    config.retry_after = std::chrono::seconds(2);
    TestServer server(config, gate.evaluator());

    std::vector<int> statuses(2, 0);
    Background first([&] {
        auto client = server.client();
        const auto result = post_json(client, "/v1/roll-gap", json::object());
        statuses[0] = result ? result->status : -1;
    });
    REQUIRE(eventually([&] { return gate.started() == 1; }));  // the worker is busy
    Background second([&] {
        auto client = server.client();
        const auto result = post_json(client, "/v1/roll-gap", json::object());
        statuses[1] = result ? result->status : -1;
    });
    REQUIRE(
        eventually([&] { return server.server->pool_stats().interactive_queued == 1; }));  // queued

    auto client = server.client();
    const auto start = std::chrono::steady_clock::now();
    const auto refused = post_json(client, "/v1/roll-gap", json::object());
    const auto elapsed = std::chrono::steady_clock::now() - start;
    REQUIRE(refused);
    CHECK(refused->status == 503);
    CHECK(refused->get_header_value("Retry-After") == "2");
    CHECK(json::parse(refused->body)["code"] == "overloaded");
    CHECK(elapsed < std::chrono::milliseconds(500));  // not after the blocked computation

    // The cheap endpoints still answer while the workers are saturated.
    const auto live = client.Get("/livez");
    REQUIRE(live);
    CHECK(live->status == 200);

    gate.open();
    first.join();
    second.join();
    CHECK(statuses == std::vector<int>{200, 200});
    // Counted once the answer is written.
    CHECK(eventually(
        [&] { return server.server->metrics().request_count("POST", "/v1/roll-gap", 503) == 1; }));
}

TEST_CASE(
    "deadline: a computation past the deadline is cancelled through Control and answered 504") {
    Gate gate;  // never opened: only the Control ends these computations
    service::ServerConfig config = test_config();
    config.deadline = std::chrono::milliseconds(150);
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    const auto start = std::chrono::steady_clock::now();
    const auto result = post_json(client, "/v1/roll-gap", json::object());
    const auto elapsed = std::chrono::steady_clock::now() - start;
    REQUIRE(result);
    CHECK(result->status == 504);
    CHECK(json::parse(result->body)["code"] == "deadline_exceeded");
    CHECK(elapsed >= std::chrono::milliseconds(150));
    CHECK(elapsed < std::chrono::milliseconds(1500));
    // The worker was told to stop and is free again.
    CHECK(eventually([&] { return gate.saw_cancel() == 1; }));
    CHECK(eventually([&] { return server.server->pool_stats().busy == 0; }));
    CHECK(eventually([&] {
        return server.server->metrics_text().find("outcome=\"deadline_exceeded\"") !=
               std::string::npos;
    }));
}

TEST_CASE("deadline: the real facade stops a long sweep when its deadline passes") {
    REQUIRE(service::find_analysis(service::analyses(), "sweep") != nullptr);
    service::ServerConfig config = test_config();
    config.deadline = std::chrono::milliseconds(100);
    TestServer server(config);
    auto client = server.client();
    // 200 critical-speed searches: seconds of work without cancellation.
    const json body = {{"options",
                        {{"parameter", "/lubricant/viscosity_Pa_s"},
                         {"range", {{"from", 0.0004}, {"to", 0.0008}, {"count", 200}}}}}};
    const auto result = post_json(client, "/v1/sweeps", body);
    REQUIRE(result);
    CHECK(result->status == 504);
    CHECK(json::parse(result->body)["code"] == "deadline_exceeded");
    // Cancellation reached the computation: the workers are free well before the sweep could
    // finish.
    CHECK(eventually([&] { return server.server->pool_stats().busy == 0; },
                     std::chrono::milliseconds(1500)));
}

TEST_CASE("shutdown: readiness fails at once, in-flight work finishes, then the server stops") {
    Gate gate;
    TestServer server(test_config(), gate.evaluator());
    int status = 0;
    Background in_flight([&] {
        auto client = server.client();
        const auto result = post_json(client, "/v1/roll-gap", json::object());
        status = result ? result->status : -1;
    });
    REQUIRE(eventually([&] { return gate.started() == 1; }));

    Background stopping([&] { server.server->shutdown(); });
    REQUIRE(eventually([&] { return server.server->draining(); }));
    auto client = server.client();
    const auto ready = client.Get("/readyz");
    REQUIRE(ready);
    CHECK(ready->status == 503);
    CHECK(json::parse(ready->body)["code"] == "overloaded");
    const auto live = client.Get("/livez");
    REQUIRE(live);
    CHECK(live->status == 200);
    const auto job = post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}});
    REQUIRE(job);
    CHECK(job->status == 503);  // no new jobs while draining
    CHECK(server.server->running());

    gate.open();
    in_flight.join();
    stopping.join();
    CHECK(status == 200);  // the in-flight request completed
    CHECK_FALSE(server.server->running());
    CHECK_FALSE(client.Get("/livez"));  // nothing listens any more
}

TEST_CASE("shutdown: work still running at the drain timeout is cancelled") {
    Gate gate;  // never opened
    service::ServerConfig config = test_config();
    config.drain_timeout = std::chrono::milliseconds(100);
    TestServer server(config, gate.evaluator());
    int status = 0;
    Background in_flight([&] {
        auto client = server.client();
        const auto result = post_json(client, "/v1/roll-gap", json::object());
        status = result ? result->status : -1;
    });
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    const auto start = std::chrono::steady_clock::now();
    server.server->shutdown();
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(3));
    in_flight.join();
    CHECK(gate.saw_cancel() == 1);
    CHECK(status == 503);  // stopped by the shutdown: retry elsewhere
}

TEST_CASE("shutdown: `rollgap serve` drains on SIGTERM and exits 0") {
    const std::filesystem::path program = rollgap_program();
    // A port picked by the kernel, released for the child to bind.
    const int port = free_loopback_port();
    REQUIRE(port > 0);
    const std::string data_dir = fresh_temp_dir();  // a job store of its own
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        const std::string port_text = std::to_string(port);
        ::setenv("ROLLGAP_LOG_LEVEL", "warn", 1);
        ::execl(program.c_str(), "rollgap", "serve", "--port", port_text.c_str(), "--admin-port",
                "0", "--workers", "1", "--io-threads", "4", "--data-dir", data_dir.c_str(),
                static_cast<char*>(nullptr));
        ::_exit(127);
    }
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(0, 200'000);
    const bool ready = eventually([&] {
        const auto result = client.Get("/readyz");
        return result && result->status == 200;
    });
    CHECK(ready);
    if (ready) {
        const auto result =
            post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}});
        REQUIRE(result);
        CHECK(result->status == 200);
    }
    ::kill(child, SIGTERM);
    int status = 0;
    bool exited = false;
    for (int i = 0; i < 500 && !exited; ++i) {
        exited = ::waitpid(child, &status, WNOHANG) == child;
        if (!exited) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!exited) {
        ::kill(child, SIGKILL);
        ::waitpid(child, &status, 0);
    }
    CHECK(exited);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
}
