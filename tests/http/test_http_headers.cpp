// Request headers are bounded early (size and count: 431 problem) and a header with a NUL byte
// is refused (400 problem) instead of being cut at the NUL; the server keeps serving.

#include <doctest/doctest.h>

#include <string>

#include "support/http_test.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;

namespace {

void check_raw_problem(const std::string& response, int status, std::string_view code) {
    CAPTURE(response.substr(0, 400));
    CHECK(raw_status(response) == status);
    CHECK(raw_header(response, "Content-Type") == "application/problem+json");
    const json problem = json::parse(raw_body(response));
    CHECK(problem["status"] == status);
    CHECK(problem["code"] == code);
}

void check_still_serving(const TestServer& server) {
    auto client = server.client();
    const auto live = client.Get("/livez");
    REQUIRE(live);
    CHECK(live->status == 200);
}

}  // namespace

TEST_CASE("headers: one header line of 4 MB is refused with 431 before it is read whole") {
    TestServer server;
    RawConnection connection(server.port());
    connection.send("GET /livez HTTP/1.1\r\nHost: x\r\nX-Big: ");
    // The server refuses once the limit is passed; the rest of the line may never be sent.
    const std::string chunk(64 * 1024, 'a');
    for (int i = 0; i < 64 && connection.send(chunk); ++i) {
    }
    check_raw_problem(connection.receive([](const std::string& r) { return response_complete(r); }),
                      431, "header_fields_too_large");
    check_still_serving(server);
}

TEST_CASE("headers: 5,000 small header fields are refused with 431") {
    TestServer server;
    std::string request = "GET /livez HTTP/1.1\r\nHost: x\r\n";
    for (int i = 0; i < 5000; ++i) request += "X-H" + std::to_string(i) + ": v\r\n";
    request += "\r\n";
    check_raw_problem(raw_exchange(server.port(), request), 431, "header_fields_too_large");
    check_still_serving(server);
}

TEST_CASE("headers: a request with a few dozen ordinary headers is served") {
    TestServer server;
    std::string request = "GET /livez HTTP/1.1\r\nHost: x\r\n";
    for (int i = 0; i < 40; ++i)
        request += "X-Header-" + std::to_string(i) + ": " + std::string(100, 'v') + "\r\n";
    request += "\r\n";
    const std::string response = raw_exchange(server.port(), request);
    CHECK(raw_status(response) == 200);
}

TEST_CASE("headers: a NUL byte in a header value is refused with 400, not cut") {
    TestServer server;
    using namespace std::string_literals;
    const std::string request = "GET /livez HTTP/1.1\r\nHost: x\r\nX-Request-Id: abc\0def\r\n\r\n"s;
    check_raw_problem(raw_exchange(server.port(), request), 400, "invalid_header");
    check_still_serving(server);
}
