#pragma once
// Helpers of the HTTP service tests (test_http_*.cpp): an in-process server on an ephemeral
// loopback port, a client, raw socket exchanges, evaluators that block or run slowly, and
// bounded waiting. Only 127.0.0.1 is ever contacted.

#include "service/config.h"
#include "service/http/http_server.h"
#include "support/postgres.h"  // free_loopback_port, and PostgreSQL for the store tests

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <doctest/doctest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>
#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include "support/loopback_port.h"

namespace rollgap::test {

using nlohmann::json;

// Polls `condition` every 2 ms until it holds or `timeout` passes.
inline bool eventually(const std::function<bool()>& condition,
                       std::chrono::milliseconds timeout = std::chrono::milliseconds(5000)) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
        if (condition()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return condition();
}

// A fresh directory under the system's temporary directory, removed when the test program
// exits (a server of the test may still hold files in it until its end).
inline std::string fresh_temp_dir() {
    struct Registry {
        std::mutex mutex;
        std::vector<std::filesystem::path> dirs;
        ~Registry() {
            for (const auto& dir : dirs) {
                std::error_code ignored;
                std::filesystem::remove_all(dir, ignored);
            }
        }
    };
    static Registry registry;
    std::string pattern = (std::filesystem::temp_directory_path() / "rollgap-test-XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    std::lock_guard lock(registry.mutex);
    registry.dirs.emplace_back(pattern);
    return pattern;
}

// A small configuration for tests: loopback, any port, few threads, short drain, and a job
// store of its own (a fresh SQLite file: no test sees another's jobs).
inline service::ServerConfig test_config() {
    service::ServerConfig config;
    config.bind_address = "127.0.0.1";
    config.port = 0;
    config.admin_port = 0;
    config.workers = 2;
    config.io_threads = 8;
    config.queue_length = 8;
    config.drain_timeout = std::chrono::milliseconds(2000);
    config.instance = "test";
    config.data_dir = fresh_temp_dir();
    config.store = "sqlite:" + config.data_dir + "/jobs.db";
    // Raw exchanges send `Host: x` and nginx passes its own Host: any is served. The Host
    // check has its own tests (test_http_trust.cpp), which start from the product default.
    config.allowed_hosts = {"*"};
    return config;
}

// Collects log lines; text() may be read while the server logs.
class CapturingSink : public spdlog::sinks::base_sink<std::mutex> {
public:
    std::string text() {
        std::lock_guard lock(mutex_);
        return text_;
    }

protected:
    void sink_it_(const spdlog::details::log_msg& message) override {
        spdlog::memory_buf_t formatted;
        formatter_->format(message, formatted);
        text_.append(formatted.data(), formatted.size());
    }
    void flush_() override {}

private:
    std::string text_;
};

// A server started in process, its request log captured, and a client for it.
struct TestServer {
    std::shared_ptr<CapturingSink> sink = std::make_shared<CapturingSink>();
    std::shared_ptr<spdlog::logger> logger;
    std::unique_ptr<service::HttpServer> server;

    explicit TestServer(service::ServerConfig config = test_config(),
                        service::Evaluator evaluator = service::facade_evaluator()) {
        logger = std::make_shared<spdlog::logger>("http-test", sink);
        logger->set_pattern("%v");
        logger->set_level(spdlog::level::info);
        server = std::make_unique<service::HttpServer>(config, std::move(evaluator), logger);
        std::string error;
        REQUIRE_MESSAGE(server->start(&error), error);
    }

    int port() const { return server->port(); }

    httplib::Client client(int read_timeout_s = 30) const {
        httplib::Client client("127.0.0.1", port());
        client.set_connection_timeout(2, 0);
        client.set_read_timeout(read_timeout_s, 0);
        return client;
    }

    std::string log_text() { return sink->text(); }
};

inline httplib::Result post_json(httplib::Client& client, const std::string& path, const json& body,
                                 const httplib::Headers& headers = {}) {
    return client.Post(path.c_str(), headers, body.dump(), "application/json");
}

inline json body_json(const httplib::Result& result) {
    REQUIRE(result);
    return json::parse(result->body);
}

// Polls the job at `location` until it finished (or `timeout` passes); its last document.
inline json poll_until_finished(
    httplib::Client& client, const std::string& location,
    std::chrono::milliseconds timeout = std::chrono::milliseconds(10000)) {
    json document;
    eventually(
        [&] {
            const auto result = client.Get(location.c_str());
            if (!result || result->status != 200) return false;
            document = json::parse(result->body);
            const std::string state = document["state"];
            return state == "succeeded" || state == "failed" || state == "cancelled";
        },
        timeout);
    return document;
}

// POST /v1/jobs, which must answer 202 with the job's Location; the Location.
inline std::string submit_job(httplib::Client& client, const json& request) {
    const auto result = post_json(client, "/v1/jobs", request);
    REQUIRE(result);
    CAPTURE(result->body);
    REQUIRE(result->status == 202);
    const std::string location = result->get_header_value("Location");
    CHECK(location == "/v1/jobs/" + json::parse(result->body)["id"].get<std::string>());
    return location;
}

// Whether `received` holds a whole HTTP response (headers and a Content-Length body).
inline bool response_complete(const std::string& received) {
    const std::size_t end = received.find("\r\n\r\n");
    if (end == std::string::npos) return false;
    const std::size_t field = received.find("Content-Length: ");
    if (field == std::string::npos || field > end) return true;  // no body
    const std::size_t length =
        std::stoul(received.substr(field + 16, received.find("\r\n", field) - field - 16));
    return received.size() >= end + 4 + length;
}

// Sends `bytes` to 127.0.0.1:port on a fresh connection and returns everything received until
// the server closes or `timeout` passes without data.
inline std::string raw_exchange(
    int port, std::string_view bytes,
    std::chrono::milliseconds timeout = std::chrono::milliseconds(2000)) {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    REQUIRE(fd >= 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    timeval tv{};
    tv.tv_sec = static_cast<time_t>(timeout.count() / 1000);
    tv.tv_usec = static_cast<suseconds_t>((timeout.count() % 1000) * 1000);
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::size_t sent = 0;
    while (sent < bytes.size()) {
        const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
        if (n <= 0) break;  // the server may close early (e.g. after a 413)
        sent += static_cast<std::size_t>(n);
    }
    std::string received;
    char buffer[4096];
    for (;;) {
        const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
        if (n <= 0) break;
        received.append(buffer, static_cast<std::size_t>(n));
        if (response_complete(received)) break;  // the server may keep the connection open
    }
    ::close(fd);
    return received;
}

// A raw connection to 127.0.0.1:port for exchanges httplib's client cannot make: pipelined
// requests, a half-closed client, a client that sends one byte at a time.
class RawConnection {
public:
    explicit RawConnection(int port) {
        fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        REQUIRE(fd_ >= 0);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_port = htons(static_cast<std::uint16_t>(port));
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        REQUIRE(::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    }
    ~RawConnection() {
        if (fd_ >= 0) ::close(fd_);
    }
    RawConnection(const RawConnection&) = delete;
    RawConnection& operator=(const RawConnection&) = delete;

    // False once the server has closed or reset the connection.
    bool send(std::string_view bytes) {
        std::size_t sent = 0;
        while (sent < bytes.size()) {
            const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
            if (n <= 0) return false;
            sent += static_cast<std::size_t>(n);
        }
        return true;
    }
    void shutdown_write() { ::shutdown(fd_, SHUT_WR); }

    // Reads until `done(received)` holds, the server closes, or `timeout` passes; returns what
    // was received so far (also kept in received()).
    std::string receive(const std::function<bool(const std::string&)>& done,
                        std::chrono::milliseconds timeout = std::chrono::milliseconds(5000)) {
        const auto until = std::chrono::steady_clock::now() + timeout;
        char buffer[8192];
        while (!done(received_) && !closed_) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                until - std::chrono::steady_clock::now());
            if (left.count() <= 0) break;
            timeval tv{};
            tv.tv_sec = static_cast<time_t>(left.count() / 1000);
            tv.tv_usec = static_cast<suseconds_t>((left.count() % 1000) * 1000 + 1);
            ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
            const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
            if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
                closed_ = true;
            } else if (n > 0) {
                received_.append(buffer, static_cast<std::size_t>(n));
            }
        }
        return received_;
    }
    // Waits for the server to close the connection; true if it did within `timeout`.
    bool closed_by_server(std::chrono::milliseconds timeout) {
        receive([](const std::string&) { return false; }, timeout);
        return closed_;
    }
    const std::string& received() const { return received_; }

private:
    int fd_ = -1;
    bool closed_ = false;
    std::string received_;
};

// How many complete responses (status line, headers, Content-Length body) `received` holds.
inline int complete_responses(std::string_view received) {
    int count = 0;
    while (response_complete(std::string(received))) {
        ++count;
        const std::size_t end = received.find("\r\n\r\n");
        std::size_t length = 0;
        const std::size_t field = received.find("Content-Length: ");
        if (field != std::string_view::npos && field < end) {
            length = std::stoul(std::string(
                received.substr(field + 16, received.find("\r\n", field) - field - 16)));
        }
        received.remove_prefix(end + 4 + length);
    }
    return count;
}

// The body of the first response in `received` (after the blank line).
inline std::string raw_body(std::string_view received) {
    const std::size_t end = received.find("\r\n\r\n");
    return end == std::string_view::npos ? std::string() : std::string(received.substr(end + 4));
}

// The value of a header of the first response in `received`, or "".
inline std::string raw_header(std::string_view received, std::string_view name) {
    const std::string head(received.substr(0, received.find("\r\n\r\n")));
    std::string lower_head = head;
    std::string lower_name(name);
    for (char& c : lower_head) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (char& c : lower_name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const std::size_t at = lower_head.find("\r\n" + lower_name + ":");
    if (at == std::string::npos) return "";
    std::size_t begin = at + 3 + name.size();
    while (begin < head.size() && head[begin] == ' ') ++begin;
    return head.substr(begin, head.find("\r\n", begin) - begin);
}

// The status code of a raw HTTP response ("HTTP/1.1 413 ..."), or 0.
inline int raw_status(std::string_view response) {
    if (response.size() < 12 || !response.starts_with("HTTP/1.")) return 0;
    return std::stoi(std::string(response.substr(9, 3)));
}

// An evaluator whose computations block until released (or cancelled through the Control),
// counting how many started and how many saw the cancellation.
class Gate {
public:
    service::Evaluator evaluator(std::function<service::Outcome(const json&)> after = nullptr) {
        return [this, after](const json& request, const core::Control& control) {
            ++started_;
            std::unique_lock lock(mutex_);
            const auto safety = std::chrono::steady_clock::now() + std::chrono::seconds(20);
            while (!open_ && !control.should_stop() && std::chrono::steady_clock::now() < safety) {
                control.report(0.5);
                opened_.wait_for(lock, std::chrono::milliseconds(2));
            }
            lock.unlock();
            if (control.should_stop()) {
                ++saw_cancel_;
                return service::problem_outcome(
                    api::make_problem(api::ProblemCode::cancelled, "cancelled"));
            }
            ++finished_;
            if (after) return after(request);
            return service::Outcome{
                200, json{{"analysis", request.value("analysis", "")}, {"result", {{"ok", true}}}},
                std::nullopt};
        };
    }
    void open() {
        {
            std::lock_guard lock(mutex_);
            open_ = true;
        }
        opened_.notify_all();
    }
    int started() const { return started_; }
    int finished() const { return finished_; }
    int saw_cancel() const { return saw_cancel_; }

private:
    std::mutex mutex_;
    std::condition_variable opened_;
    bool open_ = false;
    std::atomic<int> started_{0}, finished_{0}, saw_cancel_{0};
};

// Runs `work` on a thread and joins it on destruction.
class Background {
public:
    explicit Background(std::function<void()> work) : thread_(std::move(work)) {}
    ~Background() {
        if (thread_.joinable()) thread_.join();
    }
    void join() {
        if (thread_.joinable()) thread_.join();
    }

private:
    std::thread thread_;
};

}  // namespace rollgap::test
