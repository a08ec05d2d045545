#pragma once
// The connection layer under httplib: a listener that runs each connection's request loop
// itself, so that what httplib 0.11 (Debian's compiled library) leaves unbounded is bounded
// here, before a handler runs:
// - the request line and header fields: at most max_header_bytes in all and max_header_fields
//   lines (431), no NUL byte (400): counted while httplib reads them, byte by byte, so a 64 MB
//   header line is refused after max_header_bytes, not buffered whole;
// - a total deadline for a request to arrive (headers and body, from its first byte), not a
//   per-byte timeout: a client sending one byte every few seconds is cut off (408);
// - a total deadline for writing an answer;
// - the request line: at most max_request_line_bytes (414), so no long client text reaches
//   httplib (whose std::regex recursion touches stack in proportion to the text);
// - Range: no route serves partial content, so Range header lines are dropped as they arrive,
//   before httplib parses them (its range parser is a std::regex over the whole value, and it
//   would apply the ranges to any answer, also to refusals);
// - message framing (request smuggling): a duplicate or non-decimal Content-Length, any
//   Transfer-Encoding other than exactly "chunked", Transfer-Encoding with Content-Length, and
//   header lines httplib would skip or misread (no colon, whitespace before the colon, folded
//   lines, bare LF) are refused with 400 and the connection closes, as nginx does, so that the
//   service and a proxy in front of it never disagree on where a request ends;
// - an unread body: a connection whose request body was not read to its end closes (the rest
//   would be taken for the next request), and closes gracefully: the answer is sent, then what
//   the client still sends is read and dropped for a bounded time, so the kernel does not reset
//   the connection under the answer (a proxy would turn the refusal into a 502);
// - pipelining and half-closed clients: one buffered stream per connection (httplib makes a
//   new one per request and drops bytes read ahead), and writes do not ask whether the peer
//   still sends;
// - stop(): open connections are shut down instead of being waited for.

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <set>
#include <vector>

#include <httplib.h>

namespace rollgap::service::http {

// nginx's default large_client_header_buffers hold 4 x 8 kB; a rollgap request needs a few
// hundred bytes of headers.
inline constexpr std::size_t default_max_header_bytes = 32 * 1024;
inline constexpr std::size_t default_max_header_fields = 100;
// A rollgap target is a route and a short name or query; nginx refuses a request line over
// 8 KiB itself.
inline constexpr std::size_t default_max_request_line_bytes = 4 * 1024;

// The stack of each connection thread (httplib's ThreadPool would take the process default,
// 8 MiB, and keep whatever a request touched). Sanitizers multiply stack frames.
#if defined(__SANITIZE_ADDRESS__)
#define ROLLGAP_STACK_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ROLLGAP_STACK_SANITIZED 1
#endif
#endif
#ifdef ROLLGAP_STACK_SANITIZED
inline constexpr std::size_t connection_stack_bytes = 4 * 1024 * 1024;
#else
inline constexpr std::size_t connection_stack_bytes = 1024 * 1024;
#endif

struct ListenerLimits {
    std::size_t max_header_bytes =
        default_max_header_bytes;  // request line and header fields together
    std::size_t max_header_fields = default_max_header_fields;
    std::size_t max_request_line_bytes = default_max_request_line_bytes;
    std::chrono::milliseconds read_deadline{
        10'000};  // a request's headers and body, from its first byte
    std::chrono::milliseconds write_deadline{10'000};  // an answer, from its first byte
    std::chrono::milliseconds idle_timeout{5'000};  // between requests on a kept-alive connection
    std::size_t max_requests_per_connection = 100'000;
    // Closing with a body not read: how long, and how many bytes, to read and drop.
    std::chrono::milliseconds linger{1'000};
    std::size_t linger_bytes = 4 * 1024 * 1024;
};

// Why the connection layer stopped reading a request.
enum class Refusal {
    none,
    request_line_too_long,   // 414: the request line passed max_request_line_bytes
    header_too_large,        // 431: the header section passed max_header_bytes
    too_many_header_fields,  // 431
    header_nul,              // 400
    read_deadline,           // 408: the request did not arrive within the read deadline
    // 400, the framing of the message is ambiguous:
    duplicate_content_length,
    invalid_content_length,         // not a decimal number
    unsupported_transfer_encoding,  // anything but exactly "chunked", or given twice
    transfer_encoding_with_content_length,
    malformed_header_line,  // no colon, whitespace before it, a folded line, a bare LF
};

// httplib's task queue with threads of a given stack size (httplib::ThreadPool uses
// std::thread, whose stack size cannot be chosen).
class StackBoundedPool final : public httplib::TaskQueue {
public:
    StackBoundedPool(std::size_t threads, std::size_t stack_bytes);
    ~StackBoundedPool() override;
    StackBoundedPool(const StackBoundedPool&) = delete;
    StackBoundedPool& operator=(const StackBoundedPool&) = delete;

    void enqueue(std::function<void()> task) override;
    void shutdown() override;

    std::size_t threads() const { return threads_.size(); }

private:
    static void* run(void* self);

    std::vector<pthread_t> threads_;
    std::deque<std::function<void()>> tasks_;
    bool shutting_down_ = false;
    std::mutex mutex_;
    std::condition_variable ready_;
};

// The status line and headers of an answer as sent: httplib adds its own Connection: close or
// Keep-Alive to those a handler set, so a closing answer could say "Connection: close" twice
// and keep-alive beside it. Returns `head` with one Connection: close and no Keep-Alive when any
// Connection header says close; otherwise unchanged.
std::string one_connection_header(std::string_view head);

// A stream's answer (server-sent events) is written piece by piece for as long as it lasts:
// each piece gets the write deadline anew, from now, instead of the whole answer once.
void restart_write_deadline();

// The refusal of the request being read on this thread, if any (for the error handler and
// for handlers whose body read failed).
Refusal current_refusal();

class Connection;

class Listener : public httplib::Server {
public:
    explicit Listener(ListenerLimits limits);
    ~Listener() override;

    // Fills `response` (status, body, headers) for a refusal; required before listening.
    using RefusalRenderer = std::function<void(Refusal, httplib::Response&)>;
    void set_refusal_renderer(RefusalRenderer render) { render_refusal_ = std::move(render); }
    // httplib's logger, also called for the answers the listener writes itself. Use this,
    // not set_logger(): an answer marked "Connection: close" (a refusal whose body was not
    // read) must end the connection, or the unread body would be taken for a request.
    void set_request_logger(httplib::Logger log);

    // httplib listens with a backlog of 5 (fixed in the compiled library): a burst of new
    // connections overflows it and the kernel drops SYNs, which clients retry only after a
    // second. Calling listen() again on the bound socket raises it.
    bool raise_backlog(int backlog);

    // Stops accepting, closes idle connections and those still receiving a request at once,
    // gives the others until `grace` to finish their answer, then shuts them down. The thread
    // running listen_after_bind() returns soon after. Idempotent.
    void stop_within(std::chrono::milliseconds grace);

    std::size_t open_connections() const;

    // Runs the request loop of one connected socket on the calling thread and closes it (what
    // an accepted connection gets): for the fuzz harness, which feeds a socketpair.
    void serve_connection(socket_t sock) { process_and_close_socket(sock); }

private:
    bool process_and_close_socket(socket_t sock) override;
    void write_refusal(Connection& connection, Refusal refusal);
    void close_gracefully(socket_t sock) const;

    ListenerLimits limits_;
    RefusalRenderer render_refusal_;
    httplib::Logger log_;
    std::atomic<bool> stopping_{false};
    mutable std::mutex mutex_;
    std::set<Connection*> connections_;
};

}  // namespace rollgap::service::http
