// A job's progress as server-sent events (GET /v1/jobs/{id}/events), on a real server: the
// job's document at once and at each change, then `end` when it finishes; a comment line when
// nothing happens for the heartbeat; the streams open at once bounded (503 beyond); an
// unknown job 404; headers that keep proxies from buffering.

#include <doctest/doctest.h>

#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace job_events_test {

std::string stream_request(const std::string& location) {
    return "GET " + location + "/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
}

// The data of every `event: job` in what the stream sent so far.
std::vector<json> job_events(const std::string& received) {
    std::vector<json> events;
    const std::string marker = "event: job\ndata: ";
    for (std::size_t at = received.find(marker); at != std::string::npos;
         at = received.find(marker, at + 1)) {
        const std::size_t begin = at + marker.size();
        events.push_back(json::parse(received.substr(begin, received.find('\n', begin) - begin)));
    }
    return events;
}

}  // namespace job_events_test

namespace jet = job_events_test;

TEST_CASE("job events: the document at once and at each change, then end") {
    Gate gate;
    TestServer server(test_config(), gate.evaluator());
    auto client = server.client();
    const std::string location = submit_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    RawConnection stream(server.port());
    REQUIRE(stream.send(jet::stream_request(location)));
    const std::string first = stream.receive(
        [](const std::string& r) { return r.find("\"running\"") != std::string::npos; });
    CAPTURE(first.substr(0, 600));
    CHECK(raw_status(first) == 200);
    CHECK(raw_header(first, "Content-Type").starts_with("text/event-stream"));
    CHECK(raw_header(first, "X-Accel-Buffering") == "no");
    CHECK(raw_header(first, "Cache-Control") == "no-cache");
    REQUIRE_FALSE(jet::job_events(first).empty());
    CHECK(jet::job_events(first).back()["state"] == "running");
    gate.open();
    const std::string all = stream.receive(
        [](const std::string& r) { return r.find("\r\n0\r\n\r\n") != std::string::npos; },
        std::chrono::milliseconds(10'000));
    CAPTURE(all.substr(0, 1200));
    const auto events = jet::job_events(all);
    REQUIRE(events.size() >= 2);
    CHECK(events.back()["state"] == "succeeded");
    CHECK(events.back()["id"] == events.front()["id"]);
    CHECK(all.find("event: end\ndata: {\"reason\": \"finished\"}") != std::string::npos);
    CHECK(all.find("\r\n0\r\n\r\n") != std::string::npos);  // the stream ended
    // no event repeats the one before it: only changes are sent
    for (std::size_t i = 1; i < events.size(); ++i) CHECK(events[i] != events[i - 1]);
}

TEST_CASE("job events: a quiet stream gets a comment line each heartbeat") {
    Gate gate;
    service::ServerConfig config = test_config();
    config.event_heartbeat = std::chrono::milliseconds(200);
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    const std::string location = submit_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    RawConnection stream(server.port());
    REQUIRE(stream.send(jet::stream_request(location)));
    const std::string quiet = stream.receive([](const std::string& r) {
        std::size_t count = 0;
        for (std::size_t at = r.find(": keep-alive"); at != std::string::npos;
             at = r.find(": keep-alive", at + 1))
            ++count;
        return count >= 2;
    });
    CHECK(quiet.find(": keep-alive\n\n") != std::string::npos);
    gate.open();
}

TEST_CASE("job events: streams bounded, an unknown job 404") {
    Gate gate;
    service::ServerConfig config = test_config();
    config.max_event_streams = 1;
    TestServer server(config, gate.evaluator());
    auto client = server.client();
    const std::string location = submit_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    RawConnection open(server.port());
    REQUIRE(open.send(jet::stream_request(location)));
    REQUIRE(raw_status(open.receive([](const std::string& r) {
                return r.find("event: job") != std::string::npos;
            })) == 200);
    const auto second = client.Get((location + "/events").c_str());
    REQUIRE(second);
    CHECK(second->status == 503);
    CHECK(json::parse(second->body)["code"] == "overloaded");
    const auto unknown = client.Get("/v1/jobs/0123456789abcdef0123456789abcdef/events");
    REQUIRE(unknown);
    CHECK(unknown->status == 404);
    gate.open();
    // the stream ends with the job, and its slot is free again
    open.receive([](const std::string& r) { return r.find("\r\n0\r\n\r\n") != std::string::npos; },
                 std::chrono::milliseconds(10'000));
    CHECK(eventually([&] {
        const auto again = client.Get((location + "/events").c_str());
        return again && again->status == 200;
    }));
}
