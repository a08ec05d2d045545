// libFuzzer harness: bytes as what a client sends on one connection of the service port, through
// the real request path without a listening socket: one end of a socketpair is served by the
// service's own connection layer (service/http/listener.cpp: header limits, dropped Range lines,
// framing checks, deadlines, pipelining) and handlers, on a connection thread of the bounded
// stack size (StackBoundedPool), exactly as an accepted connection; the other end sends the
// bytes, half-closes and reads everything the service answers.
//
// Invariants: the answer is a sequence of well-formed HTTP/1.1 responses (status line, header
// fields, a body of exactly its Content-Length), each status one the service documents (never
// 500: an internal error is a bug), nothing after an answer marked "Connection: close", and the
// connection always ends (the client half-closed). Work per input is bounded: the analyses get a
// budget of polls (deterministic, as in fuzz_evaluate) and the store is a scratch SQLite file.

#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <thread>

#include <spdlog/spdlog.h>

#include "core/control.h"
#include "api/problem.h"
#include "fuzz/fuzz_input.h"
#include "service/http/listener.h"
#include "service/http/http_server.h"

using namespace rollgap;
using fuzz::require;

namespace {

// Units of work (scan speeds, sweep points, output times) one analysis may use.
constexpr int poll_budget = 64;

// The scratch directory of the store, removed at exit (after the server, declared below it).
struct ScratchDirectory {
    std::string path =
        (std::filesystem::temp_directory_path() / "rollgap-fuzz-http-XXXXXX").string();
    ~ScratchDirectory() {
        std::error_code ignored;
        std::filesystem::remove_all(path, ignored);
    }
} scratch;

std::unique_ptr<service::HttpServer> server;
std::unique_ptr<service::http::StackBoundedPool> connection_thread;

service::Evaluator budgeted_facade() {
    return [facade = service::facade_evaluator()](const nlohmann::json& request,
                                                  const core::Control& control) {
        core::Control budgeted = control;
        auto polls = std::make_shared<int>(0);
        budgeted.cancelled = [polls, &control] {
            return ++*polls > poll_budget || control.should_stop();
        };
        return facade(request, budgeted);
    };
}

// Statuses the service answers: the routes' successes, 100 Continue, 304 (the workbench's
// revalidation) and every error status of the problem table (api/problem.cpp), which the
// "Errors" table of docs/http-api.md lists; 500 (`internal`) is left out: a request must never
// reach it.
const std::set<int> documented_statuses = [] {
    std::set<int> statuses = {100, 200, 201, 202, 204, 304};
    for (const rollgap::api::ProblemKind& kind : rollgap::api::problem_kinds()) {
        if (kind.http_status != 500) statuses.insert(kind.http_status);
    }
    return statuses;
}();

std::string lower(std::string_view text) {
    std::string result(text);
    for (char& c : result) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return result;
}

// Checks `received` response by response.
// `head_requests`: the input holds a HEAD request, whose answer carries a Content-Length but
// no body (RFC 9110 §9.3.2); such an answer is followed directly by the next status line or the
// end of the stream.
void check_answers(std::string_view received, bool head_requests) {
    bool closed = false;
    while (!received.empty()) {
        require(!closed, "an answer after Connection: close");
        require(received.starts_with("HTTP/1.1 ") && received.size() >= 13 && received[12] == ' ',
                "a response does not start with an HTTP/1.1 status line");
        const int status = std::atoi(std::string(received.substr(9, 3)).c_str());
        require(documented_statuses.count(status) == 1, "a status the service does not document");
        const std::size_t end = received.find("\r\n\r\n");
        require(end != std::string_view::npos, "a response without the end of its header");
        const std::string head = lower(received.substr(0, end + 2));
        std::size_t length = 0;
        if (status != 100 && status != 204) {
            const std::size_t field = head.find("\r\ncontent-length: ");
            require(field != std::string::npos, "a response without Content-Length");
            length = std::strtoul(head.c_str() + field + 18, nullptr, 10);
        }
        closed = head.find("\r\nconnection: close\r\n") != std::string::npos;
        if (head_requests) {
            const std::string_view after = received.substr(end + 4);
            if (after.empty() || after.starts_with("HTTP/1.1 ")) length = 0;
        }
        require(received.size() >= end + 4 + length, "a response shorter than its Content-Length");
        received.remove_prefix(end + 4 + length);
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    spdlog::set_level(spdlog::level::off);
    require(::mkdtemp(scratch.path.data()) != nullptr, "cannot make a scratch directory");
    const std::string& directory = scratch.path;
    service::ServerConfig config;
    config.bind_address = "127.0.0.1";
    config.port = 0;  // never bound: connections come from serve_connection()
    config.admin_port = 0;
    config.workers = 1;
    config.io_threads = 1;
    config.queue_length = 2;
    config.deadline = std::chrono::milliseconds(5000);
    config.read_deadline = std::chrono::milliseconds(2000);
    config.instance = "fuzz";
    config.data_dir = directory;
    config.store = "sqlite:" + directory + "/jobs.db";
    server =
        std::make_unique<service::HttpServer>(config, budgeted_facade(), spdlog::default_logger());
    connection_thread =
        std::make_unique<service::http::StackBoundedPool>(1, service::http::connection_stack_bytes);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::array<int, 2> ends{};
    require(::socketpair(AF_UNIX, SOCK_STREAM, 0, ends.data()) == 0, "socketpair failed");
    const int client = ends[0];
    std::promise<void> served;
    connection_thread->enqueue([&served, fd = ends[1]] {
        server->serve_connection(fd);  // closes fd
        served.set_value();
    });

    // The client: sends (the service reads while answering, so neither side blocks for good),
    // half-closes, and reads until the service closes.
    // Both sides retry a call interrupted by a signal: libFuzzer's timeout timer sends SIGALRM
    // every -timeout/2 + 1 seconds, and a recv() it interrupts in the middle of an answer would
    // otherwise look like an answer shorter than its Content-Length.
    std::thread sender([client, data, size] {
        std::size_t sent = 0;
        while (sent < size) {
            const ssize_t n = ::send(client, data + sent, size - sent, MSG_NOSIGNAL);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) break;  // the service closed (a refusal)
            sent += static_cast<std::size_t>(n);
        }
        ::shutdown(client, SHUT_WR);
    });
    std::string received;
    std::array<char, 16 * 1024> buffer{};
    for (;;) {
        const ssize_t n = ::recv(client, buffer.data(), buffer.size(), 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        received.append(buffer.data(), static_cast<std::size_t>(n));
    }
    sender.join();
    served.get_future().wait();
    ::close(client);
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    check_answers(received, input.find("HEAD") != std::string_view::npos);
    return 0;
}
