// The front proxy: the service on loopback behind nginx run with the repository's own
// deploy/nginx/rollgap.conf (only its two addresses set for the test), and the hostile clients
// of a reliability probe replayed through nginx's port, the one for untrusted clients: a
// slow-loris client, header floods, a multi-range Range, pipelined requests, a half-closed
// client, bodies at and above the limit. Everything runs on 127.0.0.1 with bounded loops.

#include <doctest/doctest.h>

#include <poll.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "support/http_test.h"
#include "support/nginx.h"

using namespace rollgap;
using namespace rollgap::test;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// The limits of deploy/nginx/rollgap.conf the test replays against (docs/operations.md's table).
constexpr auto header_deadline = std::chrono::seconds(10);  // client_header_timeout
constexpr std::size_t header_line_limit = 8192;             // large_client_header_buffers 4 8k
constexpr std::size_t body_limit = 1048576;                 // client_max_body_size 1m

void skipped_without_nginx() {
    MESSAGE(
        "nginx is not installed (scripts/install-deps.sh installs it): front proxy test skipped");
}

// A socket connected to 127.0.0.1:port, or -1.
int connect_loopback(int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return -1;
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) return fd;
    ::close(fd);
    return -1;
}

// Whether something accepts connections on 127.0.0.1:port.
bool accepts_connections(int port) {
    const int fd = connect_loopback(port);
    if (fd >= 0) ::close(fd);
    return fd >= 0;
}

// A connected socket to 127.0.0.1:port, closed on destruction.
class Connection {
public:
    explicit Connection(int port) : fd_(connect_loopback(port)) {
        REQUIRE(fd_ >= 0);
        // A send never blocks the test for long, whatever the peer does.
        timeval tv{2, 0};
        ::setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    }
    Connection(const Connection&) = delete;
    Connection& operator=(const Connection&) = delete;
    ~Connection() { ::close(fd_); }

    // Sends all of `bytes`; false once the peer closed or reset the connection.
    bool send(std::string_view bytes) {
        std::size_t sent = 0;
        while (sent < bytes.size()) {
            const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
            if (n <= 0) return false;
            sent += static_cast<std::size_t>(n);
        }
        return true;
    }

    // Whether something (data, end of stream or an error) can be read within `timeout`.
    bool readable(std::chrono::milliseconds timeout) {
        pollfd entry{fd_, POLLIN, 0};
        return ::poll(&entry, 1, static_cast<int>(timeout.count())) > 0;
    }

    // Everything received until the peer closes, `complete` holds, or `timeout` passes
    // without data.
    std::string receive(std::chrono::milliseconds timeout = std::chrono::milliseconds(3000),
                        const std::function<bool(const std::string&)>& complete = nullptr) {
        std::string received;
        char buffer[8192];
        while (readable(timeout)) {
            const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
            if (n <= 0) break;
            received.append(buffer, static_cast<std::size_t>(n));
            if (complete && complete(received)) break;
        }
        return received;
    }

    void shutdown_write() { ::shutdown(fd_, SHUT_WR); }

private:
    int fd_;
};

// The header field `name` of a raw response ("" if absent), case as nginx writes it.
std::string raw_header(const std::string& response, const std::string& name) {
    const std::size_t end = response.find("\r\n\r\n");
    const std::size_t at = response.find("\r\n" + name + ": ");
    if (at == std::string::npos || at > end) return "";
    const std::size_t value = at + name.size() + 4;
    return response.substr(value, response.find("\r\n", value) - value);
}

std::string raw_body(const std::string& response) {
    const std::size_t end = response.find("\r\n\r\n");
    return end == std::string::npos ? "" : response.substr(end + 4);
}

// A raw response that is a problem of the front proxy: status, media type, and the same
// members as the service's problems.
void check_problem(const std::string& response, int status, const std::string& code) {
    CAPTURE(response.substr(0, 600));
    CHECK(raw_status(response) == status);
    CHECK(raw_header(response, "Content-Type") == "application/problem+json");
    CHECK_FALSE(raw_header(response, "X-Request-Id").empty());
    const json problem = json::parse(raw_body(response), nullptr, false);
    REQUIRE_FALSE(problem.is_discarded());
    CHECK(problem["status"] == status);
    CHECK(problem["code"] == code);
    CHECK(problem["type"] == "https://rollgap.dev/problems/" + code);
    CHECK(problem["title"].is_string());
    CHECK(problem["detail"].is_string());
}

// The service in process on loopback (few connection threads, so that a proxy which let slow
// clients through would starve it at once) behind nginx with the product configuration.
struct FrontProxy {
    TestServer service;
    int port;
    Nginx nginx;

    explicit FrontProxy(const std::string& name, service::ServerConfig service_config = config(4),
                        service::Evaluator evaluator = service::facade_evaluator())
        : service(service_config, std::move(evaluator)), port(free_loopback_port()),
          nginx(std::filesystem::temp_directory_path() /
                    ("rollgap-front-" + name + "-" + std::to_string(::getpid())),
                product_proxy_config(port, service.port())) {
        httplib::Client probe = client();
        const bool up = eventually([&] {
            const auto result = probe.Get("/readyz");
            return result && result->status == 200;
        });
        CAPTURE(nginx.error_log());
        REQUIRE(up);
    }

    static service::ServerConfig config(int io_threads) {
        service::ServerConfig config = test_config();
        config.io_threads = static_cast<std::size_t>(io_threads);
        return config;
    }

    httplib::Client client() const {
        httplib::Client client("127.0.0.1", port);
        client.set_connection_timeout(2, 0);
        client.set_read_timeout(30, 0);
        return client;
    }

    // The service's request log lines that mention `text`.
    bool service_logged(const std::string& text) {
        return service.log_text().find(text) != std::string::npos;
    }
};

const json quick_request = {{"options", {{"distributions", false}}}};

std::string post_request(const std::string& path, const std::string& body,
                         const std::string& extra_headers = "") {
    return "POST " + path +
           " HTTP/1.1\r\nHost: rollgap\r\nContent-Type: application/json\r\nContent-Length: " +
           std::to_string(body.size()) + "\r\n" + extra_headers + "\r\n" + body;
}

}  // namespace

TEST_CASE(
    "front proxy: a slow-loris client is cut off by nginx's header deadline, and the service never sees it") {
    if (!nginx_installed()) return skipped_without_nginx();
    FrontProxy proxy("slowloris");
    // Twice as many slow clients as the service has connection threads: had nginx passed them
    // on, nothing else would be answered.
    constexpr int slow_clients = 8;
    constexpr auto drip = std::chrono::seconds(2);
    struct Outcome {
        std::chrono::milliseconds closed_after{-1};
        int bytes_sent = 0;
        std::string received;
    };
    std::vector<Outcome> outcomes(slow_clients);
    const auto start = Clock::now();
    {
        std::vector<std::unique_ptr<Background>> clients;
        for (int i = 0; i < slow_clients; ++i) {
            clients.push_back(std::make_unique<Background>([&, i] {
                Outcome& outcome = outcomes[static_cast<std::size_t>(i)];
                Connection connection(proxy.port);
                const std::string request =
                    "GET /livez HTTP/1.1\r\nHost: rollgap\r\nX-Slow: " + std::string(64, 'a');
                // One byte every 2 s, for at most 24 s (a header that never ends).
                for (std::size_t k = 0; k < 12; ++k) {
                    if (!connection.send(request.substr(k, 1))) break;
                    ++outcome.bytes_sent;
                    if (connection.readable(drip)) {
                        outcome.received = connection.receive(std::chrono::milliseconds(100));
                        break;
                    }
                }
                outcome.closed_after =
                    std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
            }));
        }
        // Meanwhile normal requests through the same port are answered at once.
        httplib::Client client = proxy.client();
        for (int round = 0; round < 3; ++round) {
            std::this_thread::sleep_for(std::chrono::seconds(2));
            const auto answered_from = Clock::now();
            const auto result = post_json(client, "/v1/roll-gap", quick_request);
            REQUIRE(result);
            CHECK(result->status == 200);
            CHECK(Clock::now() - answered_from < std::chrono::seconds(2));
        }
    }
    for (const Outcome& outcome : outcomes) {
        CAPTURE(outcome.closed_after.count());
        CAPTURE(outcome.bytes_sent);
        // Cut off by the total header deadline although a byte arrived every 2 s (a per-byte
        // timeout would have kept it open), within one drip of the deadline.
        CHECK(outcome.closed_after >= header_deadline - std::chrono::milliseconds(500));
        CHECK(outcome.closed_after <= header_deadline + drip + std::chrono::seconds(1));
        CHECK(outcome.bytes_sent >= 4);
        // No answer (nginx closes without a 408): nothing for a slow client to wait for.
        CHECK(outcome.received.empty());
    }
    // None of the slow requests reached the service; the service still answers directly.
    CHECK_FALSE(proxy.service_logged("path=/livez"));
    httplib::Client direct = proxy.service.client();
    const auto alive = direct.Get("/livez");
    REQUIRE(alive);
    CHECK(alive->status == 200);
}

TEST_CASE(
    "front proxy: header floods get 431 problem details early, and nginx's memory stays bounded") {
    if (!nginx_installed()) return skipped_without_nginx();
    FrontProxy proxy("flood");
    const pid_t worker = proxy.nginx.worker_pid();
    REQUIRE(worker > 0);
    const long rss_before = resident_kib(worker);

    // Sends `head` and then `filler` repeatedly (never the end of the header) until `total`
    // bytes are offered or nginx closes; stops at nginx's answer unless `past_answer`. Returns
    // the answer and the bytes sent before it arrived.
    const auto flood = [&](const std::string& head, const std::string& filler, std::size_t total,
                           bool past_answer) {
        Connection connection(proxy.port);
        std::size_t sent = 0;
        std::size_t sent_before_answer = 0;
        bool open = connection.send(head);
        while (open && sent < total) {
            if (sent_before_answer == 0 && connection.readable(std::chrono::milliseconds(0))) {
                sent_before_answer = sent;
                if (!past_answer) break;
            }
            open = connection.send(filler);
            sent += filler.size();
        }
        if (sent_before_answer == 0) sent_before_answer = sent;
        return std::make_pair(
            connection.receive(std::chrono::milliseconds(3000), response_complete),
            sent_before_answer);
    };
    const std::string request_line = "GET /livez HTTP/1.1\r\nHost: rollgap\r\n";

    SUBCASE("one header line of up to 16 MiB") {
        const auto answer =
            flood(request_line + "X-Flood: ", std::string(65536, 'a'), 16u << 20, false);
        check_problem(answer.first, 431, "header_fields_too_large");
        MESSAGE("one huge header line: 431 after " << answer.second << " bytes");
        // The header never ended: nginx answered as soon as the line outgrew its buffer.
        CHECK(answer.second < (16u << 20));
    }
    SUBCASE("a million small headers") {
        std::string headers;
        for (int i = 0; i < 500; ++i) headers += "X-Flood-" + std::to_string(i) + ": v\r\n";
        // 2000 batches of 500 headers (about 15 MiB), never the blank line that ends them.
        const auto answer = flood(request_line, headers, 2000 * headers.size(), false);
        check_problem(answer.first, 431, "header_fields_too_large");
        MESSAGE("small headers: 431 after " << answer.second << " bytes");
        CHECK(answer.second < 2000 * headers.size());
    }
    SUBCASE("a request line longer than a header buffer: 414") {
        const std::string line = "GET /" + std::string(header_line_limit + 100, 'a') +
                                 " HTTP/1.1\r\nHost: rollgap\r\n\r\n";
        check_problem(raw_exchange(proxy.port, line), 414, "uri_too_long");
    }
    SUBCASE("a header line just under the limit still passes") {
        const std::string request = "GET /readyz HTTP/1.1\r\nHost: rollgap\r\nX-Long: " +
                                    std::string(header_line_limit - 100, 'a') +
                                    "\r\nConnection: close\r\n\r\n";
        CHECK(raw_status(raw_exchange(proxy.port, request)) == 200);
    }
    SUBCASE("a NUL byte in a header value: 400") {
        const std::string request = request_line + "X-Nul: a" + std::string(1, '\0') + "b\r\n\r\n";
        check_problem(raw_exchange(proxy.port, request), 400, "unreadable_input");
    }
    SUBCASE("16 clients at once, 4 MiB of header line each") {
        std::vector<std::unique_ptr<Background>> clients;
        std::vector<int> statuses(16, 0);
        for (int i = 0; i < 16; ++i) {
            clients.push_back(std::make_unique<Background>([&, i] {
                // The whole 4 MiB, also after the answer: nginx reads and discards it.
                statuses[static_cast<std::size_t>(i)] = raw_status(
                    flood(request_line + "X-Flood: ", std::string(65536, 'b'), 4u << 20, true)
                        .first);
            }));
        }
        clients.clear();
        CHECK(std::count(statuses.begin(), statuses.end(), 431) == 16);
        const long rss_after = resident_kib(worker);
        MESSAGE("nginx worker RSS: " << rss_before << " KiB before, " << rss_after
                                     << " KiB after 16 floods");
        // 64 MiB offered; each connection holds at most 1 KiB + 4 x 8 KiB of header buffers.
        CHECK(rss_after - rss_before < 4096);
    }
    // The service saw none of it and answers as before.
    CHECK_FALSE(proxy.service_logged("path=/livez"));
    httplib::Client client = proxy.client();
    const auto result = post_json(client, "/v1/roll-gap", quick_request);
    REQUIRE(result);
    CHECK(result->status == 200);
}

TEST_CASE("front proxy: a multi-range Range gets the whole answer, never multipart") {
    if (!nginx_installed()) return skipped_without_nginx();
    FrontProxy proxy("range");
    httplib::Client client = proxy.client();
    const auto whole = client.Get("/openapi.json");
    REQUIRE(whole);
    REQUIRE(whole->status == 200);

    // 1000 overlapping ranges (3 KiB of header): the service alone would answer a
    // multipart/byteranges body 1000 times the document.
    std::string ranges = "bytes=0-";
    for (int i = 1; i < 1000; ++i) ranges += ",0-";
    const auto ranged = client.Get("/openapi.json", {{"Range", ranges}});
    REQUIRE(ranged);
    CHECK(ranged->status == 200);
    CHECK(ranged->get_header_value("Content-Type") == whole->get_header_value("Content-Type"));
    CHECK_FALSE(ranged->has_header("Content-Range"));
    CHECK(ranged->body == whole->body);

    // An error answered to a request with a Range stays a problem.
    const auto refused =
        client.Post("/v1/roll-gap", {{"Range", "bytes=0-0,1-1"}},
                    R"({"scenario":{"strip":{"reduction":5}}})", "application/json");
    REQUIRE(refused);
    CHECK(refused->status == 422);
    CHECK(refused->get_header_value("Content-Type") == "application/problem+json");
    const auto missing = client.Get("/v1/no-such-route", {{"Range", "bytes=0-0,1-1"}});
    REQUIRE(missing);
    CHECK(missing->status == 404);
    CHECK(missing->get_header_value("Content-Type") == "application/problem+json");
}

TEST_CASE("front proxy: pipelined requests and a half-closed client are all answered") {
    if (!nginx_installed()) return skipped_without_nginx();
    FrontProxy proxy("pipeline");
    SUBCASE("two requests in one write") {
        Connection connection(proxy.port);
        REQUIRE(connection.send(
            post_request("/v1/roll-gap", quick_request.dump()) +
            "GET /v1/scenarios/default HTTP/1.1\r\nHost: rollgap\r\nConnection: close\r\n\r\n"));
        const std::string received = connection.receive(std::chrono::milliseconds(10000));
        CAPTURE(received.substr(0, 400));
        const std::size_t second = received.find("HTTP/1.1 ", 1);
        REQUIRE(second != std::string::npos);
        const std::string first_answer = received.substr(0, second);
        const std::string second_answer = received.substr(second);
        CHECK(raw_status(first_answer) == 200);
        CHECK(raw_status(second_answer) == 200);
        // In order: the roll gap first, then the default scenario.
        CHECK(json::parse(raw_body(first_answer))["analysis"] == "roll_gap");
        CHECK(json::parse(raw_body(second_answer)).contains("strip"));
    }
    SUBCASE("the client shuts down its sending side after the request") {
        Connection connection(proxy.port);
        REQUIRE(connection.send(post_request("/v1/roll-gap", quick_request.dump())));
        connection.shutdown_write();
        const std::string received =
            connection.receive(std::chrono::milliseconds(10000), response_complete);
        CAPTURE(received.substr(0, 400));
        CHECK(raw_status(received) == 200);
        CHECK(json::parse(raw_body(received))["analysis"] == "roll_gap");
    }
}

TEST_CASE(
    "front proxy: bodies up to the service's limit pass, larger ones get 413 problem details from nginx") {
    if (!nginx_installed()) return skipped_without_nginx();
    FrontProxy proxy("body");
    // A valid request padded with spaces to exactly the limit: both limits are the same number.
    std::string at_limit = quick_request.dump();
    at_limit.append(body_limit - at_limit.size(), ' ');
    httplib::Client client = proxy.client();
    const auto accepted = client.Post("/v1/roll-gap", at_limit, "application/json");
    REQUIRE(accepted);
    CHECK(accepted->status == 200);

    SUBCASE("declared one byte too large: refused before the body is sent") {
        Connection connection(proxy.port);
        REQUIRE(connection.send(
            "POST /v1/roll-gap HTTP/1.1\r\nHost: rollgap\r\nContent-Type: application/json\r\n"
            "Content-Length: " +
            std::to_string(body_limit + 1) + "\r\n\r\n"));
        check_problem(connection.receive(std::chrono::milliseconds(3000), response_complete), 413,
                      "payload_too_large");
    }
    SUBCASE("chunked, growing past the limit") {
        Connection connection(proxy.port);
        REQUIRE(connection.send(
            "POST /v1/roll-gap HTTP/1.1\r\nHost: rollgap\r\nContent-Type: application/json\r\n"
            "Transfer-Encoding: chunked\r\n\r\n"));
        const std::string chunk = "10000\r\n" + std::string(0x10000, ' ') + "\r\n";
        for (int i = 0; i < 32 && !connection.readable(std::chrono::milliseconds(0)); ++i) {
            if (!connection.send(chunk)) break;
        }
        check_problem(connection.receive(std::chrono::milliseconds(3000), response_complete), 413,
                      "payload_too_large");
    }
    // The service never saw the oversized requests.
    CHECK(proxy.service.server->metrics().request_count("POST", "/v1/roll-gap", 413) == 0);
}

TEST_CASE("front proxy: more than 16 requests of one address in progress get 429 problem details") {
    if (!nginx_installed()) return skipped_without_nginx();
    // Room in the service for every request (2 running, 30 waiting), so only nginx refuses.
    service::ServerConfig config = FrontProxy::config(64);
    config.queue_length = 32;
    Gate gate;
    FrontProxy proxy("limit", config, gate.evaluator());
    constexpr int clients = 20;
    std::vector<int> statuses(clients, 0);
    std::vector<std::string> bodies(clients);
    std::atomic<int> refused{0};
    {
        std::vector<std::unique_ptr<Background>> requests;
        for (int i = 0; i < clients; ++i) {
            requests.push_back(std::make_unique<Background>([&, i] {
                httplib::Client client = proxy.client();
                const auto result = post_json(client, "/v1/roll-gap", quick_request);
                if (!result) return;
                statuses[static_cast<std::size_t>(i)] = result->status;
                bodies[static_cast<std::size_t>(i)] = result->body;
                if (result->status == 429) {
                    CHECK(result->get_header_value("Retry-After") == "1");
                    CHECK(result->get_header_value("Content-Type") == "application/problem+json");
                    ++refused;
                }
            }));
        }
        // The refusals come while the 16 others are held in the service.
        CHECK(
            eventually([&] { return refused == clients - 16; }, std::chrono::milliseconds(10000)));
        CHECK(eventually([&] { return gate.started() == 2; }));
        gate.open();
    }
    CHECK(std::count(statuses.begin(), statuses.end(), 200) == 16);
    CHECK(std::count(statuses.begin(), statuses.end(), 429) == clients - 16);
    for (int i = 0; i < clients; ++i) {
        if (statuses[static_cast<std::size_t>(i)] != 429) continue;
        const json problem = json::parse(bodies[static_cast<std::size_t>(i)]);
        CHECK(problem["code"] == "too_many_connections");
        CHECK(problem["status"] == 429);
    }
}

TEST_CASE("front proxy: request ids are forwarded, and nginx's own errors are problem details") {
    if (!nginx_installed()) return skipped_without_nginx();
    FrontProxy proxy("ids");
    httplib::Client client = proxy.client();
    SUBCASE("a valid client id reaches the service and comes back") {
        const auto result =
            post_json(client, "/v1/roll-gap", quick_request, {{"X-Request-Id", "probe-42.a:b"}});
        REQUIRE(result);
        CHECK(result->get_header_value("X-Request-Id") == "probe-42.a:b");
        CHECK(eventually([&] { return proxy.service_logged("id=probe-42.a:b "); }));
        CHECK(eventually([&] {
            return proxy.nginx.access_log().find("id=probe-42.a:b ") != std::string::npos;
        }));
    }
    SUBCASE("an id the service would refuse is replaced by nginx's, shared by both logs") {
        const auto result =
            post_json(client, "/v1/roll-gap", quick_request, {{"X-Request-Id", "has spaces"}});
        REQUIRE(result);
        const std::string id = result->get_header_value("X-Request-Id");
        CHECK(id.size() == 32);
        CHECK(id.find_first_not_of("0123456789abcdef") == std::string::npos);
        CHECK(eventually([&] { return proxy.service_logged("id=" + id + " "); }));
        CHECK(eventually(
            [&] { return proxy.nginx.access_log().find("id=" + id + " ") != std::string::npos; }));
    }
    SUBCASE("a request line nginx cannot parse") {
        check_problem(raw_exchange(proxy.port, "GARBAGE\r\n\r\n"), 400, "unreadable_input");
    }
    SUBCASE("the proxy's internal error pages are not routes") {
        check_problem(
            raw_exchange(proxy.port,
                         "GET /.rollgap-proxy/problem/400 HTTP/1.1\r\nHost: rollgap\r\n\r\n"),
            404, "not_found");
    }
}

TEST_CASE("front proxy: a service that does not answer is a 502 problem with Retry-After") {
    if (!nginx_installed()) return skipped_without_nginx();
    // Nothing listens on the service's port.
    const int nobody = free_loopback_port();
    const int port = free_loopback_port();
    Nginx nginx(std::filesystem::temp_directory_path() /
                    ("rollgap-front-down-" + std::to_string(::getpid())),
                product_proxy_config(port, nobody));
    REQUIRE(eventually([&] { return accepts_connections(port); }));
    const std::string answer = raw_exchange(port, "GET /readyz HTTP/1.1\r\nHost: rollgap\r\n\r\n");
    check_problem(answer, 502, "service_unavailable");
    CHECK(raw_header(answer, "Retry-After") == "1");
}

TEST_CASE(
    "front proxy: the Kubernetes pod wires nginx and the service with the configuration's addresses") {
    const std::string conf =
        read_text_file(repository_root() / "deploy" / "nginx" / "rollgap.conf");
    const std::string pod =
        read_text_file(repository_root() / "deploy" / "kubernetes" / "deployment.yaml");
    const std::string kustomization =
        read_text_file(repository_root() / "deploy" / "kustomization.yaml");
    REQUIRE_FALSE(conf.empty());
    REQUIRE_FALSE(pod.empty());
    // The addresses product_proxy_config() replaces are the ones the pod uses.
    CHECK(conf.find("\n        listen 8080;") != std::string::npos);
    CHECK(conf.find("server 127.0.0.1:8090 ") != std::string::npos);
    CHECK(pod.find("- name: http\n              containerPort: 8080") != std::string::npos);
    CHECK(pod.find("- name: ROLLGAP_BIND\n              value: \"127.0.0.1\"") !=
          std::string::npos);
    CHECK(pod.find("- name: ROLLGAP_PORT\n              value: \"8090\"") != std::string::npos);
    // nginx runs the generated ConfigMap's file, the file this test runs.
    CHECK(kustomization.find("- name: rollgap-nginx\n    files:\n      - nginx/rollgap.conf") !=
          std::string::npos);
    CHECK(pod.find("name: rollgap-nginx") != std::string::npos);
    CHECK(pod.find("-c /etc/rollgap/nginx/rollgap.conf") != std::string::npos);
    // The only public port is nginx's: the service is not a container port of its own.
    CHECK(pod.find("containerPort: 8090") == std::string::npos);
}

TEST_CASE("front proxy: an early refusal of a 200 kB body is the service's own answer, not 502") {
    // The service refuses these before reading the body and closes the connection; closing
    // with the body unread reset the connection under the answer, and nginx turned the
    // service's 415, 404 or 405 into a 502.
    REQUIRE_MESSAGE(nginx_installed(), "nginx is not installed (scripts/install-deps.sh)");
    FrontProxy proxy("early-refusal");
    httplib::Client client = proxy.client();
    const std::string body(200 * 1000, ' ');
    struct Case {
        const char* method;
        const char* path;
        const char* content_type;
        int status;
        const char* code;
    };
    for (const Case& c :
         {Case{"POST", "/v1/roll-gap", "text/plain", 415, "unsupported_media_type"},
          Case{"POST", "/v1/nothing", "application/json", 404, "not_found"},
          Case{"PUT", "/v1/roll-gap", "application/json", 405, "method_not_allowed"}}) {
        for (int round = 0; round < 3; ++round) {
            CAPTURE(c.path);
            CAPTURE(round);
            const auto result = std::string(c.method) == "POST"
                                    ? client.Post(c.path, body, c.content_type)
                                    : client.Put(c.path, body, c.content_type);
            REQUIRE(result);
            CAPTURE(result->body.substr(0, 300));
            CHECK(result->status == c.status);
            CHECK(json::parse(result->body, nullptr, false).value("code", "") == c.code);
        }
    }
    CHECK(proxy.nginx.error_log().find("reset by peer") == std::string::npos);
}

TEST_CASE(
    "front proxy: a job's events pass through nginx as they happen (the document, heartbeats, "
    "the end), and a client that goes away frees its stream") {
    if (!nginx_installed()) return skipped_without_nginx();
    Gate gate;
    service::ServerConfig config = FrontProxy::config(8);
    config.event_heartbeat = std::chrono::milliseconds(200);
    config.max_event_streams = 1;  // a stream nginx kept open would refuse the next one
    FrontProxy proxy("events", config, gate.evaluator());
    auto client = proxy.client();
    const std::string location = submit_job(client, {{"analysis", "roll_gap"}});
    REQUIRE(eventually([&] { return gate.started() == 1; }));
    const std::string request =
        "GET " + location +
        "/events HTTP/1.1\r\nHost: rollgap\r\nAccept: text/event-stream\r\n\r\n";
    const auto keep_alives = [](const std::string& received) {
        int count = 0;
        for (auto at = received.find(": keep-alive"); at != std::string::npos;
             at = received.find(": keep-alive", at + 1))
            ++count;
        return count;
    };
    {
        // While the job runs, nothing finishes the answer: what arrives, nginx passed on as the
        // service wrote it (buffered, it would hold the first event and every heartbeat).
        RawConnection stream(proxy.port);
        REQUIRE(stream.send(request));
        const std::string early = stream.receive(
            [&](const std::string& r) {
                return r.find("event: job") != std::string::npos && keep_alives(r) >= 2;
            },
            std::chrono::milliseconds(5000));
        CAPTURE(early.substr(0, 800));
        CHECK(raw_status(early) == 200);
        CHECK(raw_header(early, "Content-Type").starts_with("text/event-stream"));
        CHECK(early.find("\"running\"") != std::string::npos);
        CHECK(keep_alives(early) >= 2);
        CHECK(gate.finished() == 0);
    }  // the client goes away with the job still running

    // nginx closes its side, the service's next heartbeat fails and the one slot is free.
    std::optional<RawConnection> again;
    std::string opened;
    const bool reopened = eventually(
        [&] {
            again.emplace(proxy.port);
            if (!again->send(request)) return false;
            opened = again->receive([](const std::string& r) {
                return r.find("event: job") != std::string::npos ||
                       r.find("\r\n\r\n{") != std::string::npos;
            });
            if (raw_status(opened) == 200) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(50));  // 503 until then
            return false;
        },
        std::chrono::milliseconds(5000));
    CAPTURE(opened.substr(0, 800));
    REQUIRE(reopened);
    gate.open();
    const std::string all = again->receive(
        [](const std::string& r) { return r.find("\r\n0\r\n\r\n") != std::string::npos; },
        std::chrono::milliseconds(10'000));
    CAPTURE(all.substr(0, 1500));
    CHECK(all.find("\"succeeded\"") != std::string::npos);
    CHECK(all.find("event: end\ndata: {\"reason\": \"finished\"}") != std::string::npos);
    CHECK(all.find("\r\n0\r\n\r\n") != std::string::npos);  // nginx ended its answer too
}
