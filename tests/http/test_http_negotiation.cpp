// What a client negotiates with every route, tested on a real server: an Accept header that
// admits none of the route's media types is a 406 problem (never JSON it did not ask for); a
// route answering JSON or CSV says Vary: Accept; a POST without Content-Length has an empty
// body (RFC 9112 §6.3) and is answered at once, not at the read deadline; a closing answer
// carries one Connection: close and no Keep-Alive; a 202 and a running job's GET carry the
// poll hint Retry-After; DELETE of a job answers 200 and the job in every case.

#include "service/http/listener.h"

#include <doctest/doctest.h>

#include <chrono>
#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace negotiation_test {

// How many header lines of the first response in `received` are named `name` (any case).
int header_count(std::string_view received, std::string_view name) {
    std::string head(received.substr(0, received.find("\r\n\r\n") + 2));
    for (char& c : head) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    std::string needle = "\r\n" + std::string(name) + ":";
    for (char& c : needle) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    int count = 0;
    for (std::size_t at = head.find(needle); at != std::string::npos;
         at = head.find(needle, at + 1))
        ++count;
    return count;
}

}  // namespace negotiation_test

namespace nt = negotiation_test;

TEST_CASE("negotiation: an Accept that admits none of a route's media types is a 406 problem") {
    TestServer server;
    auto client = server.client();
    const auto xml =
        post_json(client, "/v1/stability", json::object(), {{"Accept", "application/xml"}});
    REQUIRE(xml);
    CHECK(xml->status == 406);
    CHECK(xml->get_header_value("Content-Type") == "application/problem+json");
    const json problem = json::parse(xml->body);
    CHECK(problem["code"] == "not_acceptable");
    CHECK(problem["detail"].get<std::string>().find("application/json or text/csv") !=
          std::string::npos);
    // a job's submission answers JSON only: CSV alone is refused, nothing is queued
    const auto csv_job =
        post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}}, {{"Accept", "text/csv"}});
    REQUIRE(csv_job);
    CHECK(csv_job->status == 406);
    CHECK(body_json(client.Get("/v1/jobs"))["jobs"].empty());
    // what a client may send: JSON among others, a wildcard, a lower quality
    for (const char* accept : {"text/csv, application/json;q=0.5", "*/*", "application/*",
                               "text/html,application/xhtml+xml,*/*;q=0.8"}) {
        CAPTURE(accept);
        const auto job =
            post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}}, {{"Accept", accept}});
        REQUIRE(job);
        CHECK(job->status == 202);
    }
    // q=0 refuses a type: JSON refused, CSV offered by the route is still admitted
    const auto csv_only = post_json(client, "/v1/stability", json::object(),
                                    {{"Accept", "application/json;q=0, text/csv"}});
    REQUIRE(csv_only);
    CHECK(csv_only->status == 200);
    CHECK(csv_only->get_header_value("Content-Type").starts_with("text/csv"));
    const auto metrics = client.Get("/metrics", {{"Accept", "application/json"}});
    REQUIRE(metrics);
    CHECK(metrics->status == 406);
    const auto openapi = client.Get("/openapi.json", {{"Accept", "text/csv"}});
    REQUIRE(openapi);
    CHECK(openapi->status == 406);
}

TEST_CASE("negotiation: routes that answer JSON or CSV say Vary: Accept, the others do not") {
    TestServer server;
    auto client = server.client();
    const auto stability =
        post_json(client, "/v1/stability", {{"options", {{"critical_speed", false}}}});
    REQUIRE(stability);
    CHECK(stability->get_header_value("Vary") == "Accept");
    const auto evaluate = post_json(client, "/v1/evaluate", {{"options", {{"detail", "summary"}}}});
    REQUIRE(evaluate);
    CHECK_FALSE(evaluate->has_header("Vary"));  // evaluate has no table: JSON whatever the Accept
    const auto created = post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}});
    REQUIRE(created);
    CHECK_FALSE(created->has_header("Vary"));
    const auto job = client.Get(created->get_header_value("Location").c_str());
    REQUIRE(job);
    CHECK(job->get_header_value("Vary") == "Accept");
}

TEST_CASE("negotiation: a POST without Content-Length has an empty body, answered at once") {
    service::ServerConfig config = test_config();
    config.read_deadline = std::chrono::milliseconds(20000);
    TestServer server(config);
    const auto start = std::chrono::steady_clock::now();
    const std::string answer = raw_exchange(
        server.port(),
        "POST /v1/roll-gap HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n\r\n",
        std::chrono::milliseconds(15000));
    CAPTURE(answer.substr(0, 400));
    // It used to wait for a body until the read deadline and answer 408: the request is {}.
    CHECK(raw_status(answer) == 200);
    CHECK(std::chrono::steady_clock::now() - start < config.read_deadline);
    CHECK(json::parse(raw_body(answer))["analysis"] == "roll_gap");
}

TEST_CASE("negotiation: a closing answer says Connection: close once, without Keep-Alive") {
    service::ServerConfig config = test_config();
    config.read_deadline = std::chrono::milliseconds(400);
    TestServer server(config);
    // a body that never arrives: 408 at the read deadline
    const std::string timed_out = raw_exchange(
        server.port(),
        "POST /v1/roll-gap HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
        "Content-Length: 10\r\n\r\n{",
        std::chrono::milliseconds(5000));
    CAPTURE(timed_out.substr(0, 400));
    CHECK(raw_status(timed_out) == 408);
    CHECK(nt::header_count(timed_out, "Connection") == 1);
    CHECK(raw_header(timed_out, "Connection") == "close");
    CHECK(nt::header_count(timed_out, "Keep-Alive") == 0);
    CHECK(nt::header_count(timed_out, "X-Request-Id") == 1);
    // a refused body the server does not read (415): the connection closes, said once
    const std::string refused =
        raw_exchange(server.port(),
                     "POST /v1/roll-gap HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: text/plain\r\n"
                     "Content-Length: 2\r\n\r\n{}");
    CHECK(raw_status(refused) == 415);
    CHECK(nt::header_count(refused, "Connection") == 1);
    CHECK(nt::header_count(refused, "Keep-Alive") == 0);
    // an answer on a connection that stays open keeps its Keep-Alive and no Connection: close
    const std::string kept =
        raw_exchange(server.port(), "GET /livez HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
    CHECK(raw_status(kept) == 200);
    CHECK(nt::header_count(kept, "Connection") == 0);
    CHECK(nt::header_count(kept, "Keep-Alive") == 1);
}

TEST_CASE("negotiation: one Connection header from any mix httplib and a handler write") {
    using service::http::one_connection_header;
    const std::string doubled =
        "HTTP/1.1 408 Request Timeout\r\nAccept-Ranges: none\r\nConnection: close\r\n"
        "Connection: close\r\nContent-Length: 2\r\nKeep-Alive: timeout=5, max=5\r\n\r\n";
    CHECK(one_connection_header(doubled) ==
          "HTTP/1.1 408 Request Timeout\r\nAccept-Ranges: none\r\nConnection: close\r\n"
          "Content-Length: 2\r\n\r\n");
    const std::string open = "HTTP/1.1 200 OK\r\nKeep-Alive: timeout=5, max=5\r\n\r\n{}";
    CHECK(one_connection_header(open) == open);
    CHECK(one_connection_header("{\"body\": 1}") == "{\"body\": 1}");  // not a head: as it is
}

TEST_CASE("negotiation: a 202 and an unfinished job's GET carry the poll hint Retry-After") {
    Gate gate;
    TestServer server(test_config(), gate.evaluator());
    auto client = server.client();
    const auto created = post_json(client, "/v1/jobs", {{"analysis", "roll_gap"}});
    REQUIRE(created);
    REQUIRE(created->status == 202);
    CHECK(std::stoi(created->get_header_value("Retry-After")) >= 1);
    const std::string location = created->get_header_value("Location");
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    const auto running = client.Get(location.c_str());
    REQUIRE(running);
    CHECK(json::parse(running->body)["state"] == "running");
    CHECK(running->has_header("Retry-After"));
    gate.open();
    const json done = poll_until_finished(client, location);
    REQUIRE(done["state"] == "succeeded");
    const auto finished = client.Get(location.c_str());
    REQUIRE(finished);
    CHECK_FALSE(finished->has_header("Retry-After"));
    // DELETE of a finished job: 200 and its last document, marked deleted; then gone
    const auto deleted = client.Delete(location.c_str());
    REQUIRE(deleted);
    CHECK(deleted->status == 200);
    const json last = json::parse(deleted->body);
    CHECK(last["deleted"] == true);
    CHECK(last["state"] == "succeeded");
    CHECK(last["result"]["analysis"] == "roll_gap");
    CHECK(client.Get(location.c_str())->status == 404);
}
