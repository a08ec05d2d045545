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
// - Range: no route serves partial content, so the parsed ranges are dropped before routing
//   (httplib would apply them to any answer, also to refusals);
// - pipelining and half-closed clients: one buffered stream per connection (httplib makes a
//   new one per request and drops bytes read ahead), and writes do not ask whether the peer
//   still sends;
// - stop(): open connections are shut down instead of being waited for.

#include <atomic>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <set>

#include <httplib.h>

namespace rollgap::service::http {

// nginx's default large_client_header_buffers hold 4 x 8 kB; a rollgap request needs a few
// hundred bytes of headers.
inline constexpr std::size_t default_max_header_bytes = 32 * 1024;
inline constexpr std::size_t default_max_header_fields = 100;

struct ListenerLimits {
    std::size_t max_header_bytes =
        default_max_header_bytes;  // request line and header fields together
    std::size_t max_header_fields = default_max_header_fields;
    std::chrono::milliseconds read_deadline{
        10'000};  // a request's headers and body, from its first byte
    std::chrono::milliseconds write_deadline{10'000};  // an answer, from its first byte
    std::chrono::milliseconds idle_timeout{5'000};  // between requests on a kept-alive connection
    std::size_t max_requests_per_connection = 100'000;
};

// Why the connection layer stopped reading a request.
enum class Refusal {
    none,
    request_line_too_long,   // 414
    header_too_large,        // 431: the header section passed max_header_bytes
    too_many_header_fields,  // 431
    header_nul,              // 400
    read_deadline,           // 408: the request did not arrive within the read deadline
};

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

private:
    bool process_and_close_socket(socket_t sock) override;
    void write_refusal(Connection& connection, Refusal refusal);

    ListenerLimits limits_;
    RefusalRenderer render_refusal_;
    httplib::Logger log_;
    std::atomic<bool> stopping_{false};
    mutable std::mutex mutex_;
    std::set<Connection*> connections_;
};

}  // namespace rollgap::service::http
