#include "service/http/listener.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstring>
#include <string>
#include <thread>

namespace rollgap::service::http {

using Clock = std::chrono::steady_clock;

namespace {

// Milliseconds left until `deadline`, for poll(); 0 once it passed.
int milliseconds_left(Clock::time_point deadline) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, INT_MAX));
}

// poll() for one event on one socket; >0 ready, 0 timed out, <0 error.
int wait_for(int fd, short events, int timeout_ms) {
    for (;;) {
        pollfd entry{fd, events, 0};
        const int ready = ::poll(&entry, 1, timeout_ms);
        if (ready < 0 && errno == EINTR) continue;
        return ready;
    }
}

void address_of(int fd, bool peer, std::string& ip, int& port) {
    sockaddr_storage address{};
    socklen_t length = sizeof address;
    const int got = peer ? ::getpeername(fd, reinterpret_cast<sockaddr*>(&address), &length)
                         : ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
    if (got != 0) return;
    std::array<char, INET6_ADDRSTRLEN> text{};
    if (address.ss_family == AF_INET) {
        const auto& v4 = reinterpret_cast<const sockaddr_in&>(address);
        ::inet_ntop(AF_INET, &v4.sin_addr, text.data(), text.size());
        port = ntohs(v4.sin_port);
    } else if (address.ss_family == AF_INET6) {
        const auto& v6 = reinterpret_cast<const sockaddr_in6&>(address);
        ::inet_ntop(AF_INET6, &v6.sin6_addr, text.data(), text.size());
        port = ntohs(v6.sin6_port);
    }
    ip = text.data();
}

const char* reason_phrase(int status) {
    switch (status) {
        case 400: return "Bad Request";
        case 408: return "Request Timeout";
        case 414: return "URI Too Long";
        case 431: return "Request Header Fields Too Large";
        default: return status >= 500 ? "Server Error" : "Client Error";
    }
}

}  // namespace

// One accepted connection: a buffered stream kept for all its requests, which counts the
// header bytes httplib reads through it and enforces the deadlines.
class Connection final : public httplib::Stream {
public:
    enum class Phase { idle, headers, body, answering };

    Connection(int fd, const ListenerLimits& limits) : fd_(fd), limits_(limits) {}

    // Waits for the first byte of the next request; false when none comes within `idle`.
    bool wait_for_request(std::chrono::milliseconds idle) {
        if (begin_ < end_) return true;  // pipelined: already read ahead
        return wait_for(fd_, POLLIN, static_cast<int>(idle.count())) > 0;
    }

    void begin_request() {
        phase_ = Phase::headers;
        header_bytes_ = 0;
        lines_ = 0;
        line_length_ = 0;
        previous_ = '\0';
        refusal_ = Refusal::none;
        read_deadline_ = Clock::now() + limits_.read_deadline;
        writing_ = false;
        written_ = 0;
        close_requested_ = false;
    }
    void end_request() { phase_ = Phase::idle; }

    Phase phase() const { return phase_; }
    Refusal refusal() const { return refusal_; }
    std::size_t written() const { return written_; }
    void request_close() { close_requested_ = true; }
    bool close_requested() const { return close_requested_; }
    void shut_down() { ::shutdown(fd_, SHUT_RDWR); }

    bool is_readable() const override {
        return begin_ < end_ || wait_for(fd_, POLLIN, milliseconds_left(read_deadline_)) > 0;
    }
    // Only whether a write can proceed: a client that half-closed its side still reads.
    bool is_writable() const override { return wait_for(fd_, POLLOUT, 0) > 0; }

    ssize_t read(char* data, std::size_t size) override {
        if (refusal_ != Refusal::none) return -1;
        writing_ = false;  // the next write starts an answer
        if (begin_ == end_) {
            const ssize_t filled = fill();
            if (filled <= 0) return filled;
        }
        std::size_t n = std::min(size, end_ - begin_);
        if (phase_ == Phase::headers) {
            // httplib reads the headers one byte at a time; each byte is checked before it is
            // handed over, and the bytes after the blank line belong to the body.
            std::size_t accepted = 0;
            while (accepted < n && phase_ == Phase::headers) {
                if (!accept_header_byte(buffer_[begin_ + accepted])) break;
                ++accepted;
            }
            if (accepted == 0 && refusal_ != Refusal::none) return -1;
            n = accepted;
        }
        std::memcpy(data, buffer_.data() + begin_, n);
        begin_ += n;
        return static_cast<ssize_t>(n);
    }

    ssize_t write(const char* data, std::size_t size) override {
        if (!writing_) {
            writing_ = true;
            phase_ = Phase::answering;
            write_deadline_ = Clock::now() + limits_.write_deadline;
        }
        std::size_t sent = 0;
        while (sent < size) {
            const int left = milliseconds_left(write_deadline_);
            if (left == 0) return -1;
            const int ready = wait_for(fd_, POLLOUT, left);
            if (ready < 0) return -1;
            if (ready == 0) continue;  // the deadline is checked above
            const ssize_t n = ::send(fd_, data + sent, size - sent, MSG_NOSIGNAL);
            if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
            if (n <= 0) return -1;
            sent += static_cast<std::size_t>(n);
            written_ += static_cast<std::size_t>(n);
        }
        return static_cast<ssize_t>(size);
    }

    void get_remote_ip_and_port(std::string& ip, int& port) const override {
        address_of(fd_, true, ip, port);
    }
    void get_local_ip_and_port(std::string& ip, int& port) const override {
        address_of(fd_, false, ip, port);
    }
    socket_t socket() const override { return fd_; }

private:
    // Reads what the socket has, waiting until the read deadline; 0 at the peer's end of
    // stream, -1 on error or when the deadline passed.
    ssize_t fill() {
        for (;;) {
            const int left = milliseconds_left(read_deadline_);
            if (left == 0) {
                refusal_ = Refusal::read_deadline;
                return -1;
            }
            const int ready = wait_for(fd_, POLLIN, left);
            if (ready < 0) return -1;
            if (ready == 0) continue;
            const ssize_t n = ::recv(fd_, buffer_.data(), buffer_.size(), 0);
            if (n < 0 && (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)) continue;
            if (n <= 0) return n;
            begin_ = 0;
            end_ = static_cast<std::size_t>(n);
            if (phase_ == Phase::idle) phase_ = Phase::headers;
            return n;
        }
    }

    // The request line and each header line end in CRLF; a line that is only CRLF ends the
    // headers (httplib's rule: a bare LF does not).
    bool accept_header_byte(char byte) {
        if (++header_bytes_ > limits_.max_header_bytes) {
            refusal_ = lines_ == 0 ? Refusal::request_line_too_long : Refusal::header_too_large;
            return false;
        }
        if (byte == '\0') {
            refusal_ = Refusal::header_nul;
            return false;
        }
        if (byte == '\n') {
            const bool blank = line_length_ == 1 && previous_ == '\r';
            ++lines_;
            if (blank && lines_ > 1) {
                phase_ = Phase::body;
            } else if (lines_ - 1 > limits_.max_header_fields) {
                refusal_ = Refusal::too_many_header_fields;
                return false;
            }
            line_length_ = 0;
        } else {
            ++line_length_;
        }
        previous_ = byte;
        return true;
    }

    int fd_;
    const ListenerLimits& limits_;
    std::array<char, 16 * 1024> buffer_{};
    std::size_t begin_ = 0, end_ = 0;

    std::atomic<Phase> phase_{Phase::idle};
    Refusal refusal_ = Refusal::none;
    std::size_t header_bytes_ = 0, lines_ = 0, line_length_ = 0;
    char previous_ = '\0';
    Clock::time_point read_deadline_{}, write_deadline_{};
    bool writing_ = false;
    std::size_t written_ = 0;
    bool close_requested_ = false;
};

namespace {
thread_local Connection* t_connection = nullptr;
}

Refusal current_refusal() {
    return t_connection == nullptr ? Refusal::none : t_connection->refusal();
}

Listener::Listener(ListenerLimits limits) : limits_(limits) { set_request_logger(nullptr); }

Listener::~Listener() = default;

void Listener::set_request_logger(httplib::Logger log) {
    log_ = log;
    httplib::Server::set_logger(
        [log = std::move(log)](const httplib::Request& request, const httplib::Response& response) {
            if (t_connection != nullptr && response.get_header_value("Connection") == "close") {
                t_connection->request_close();
            }
            if (log) log(request, response);
        });
}

bool Listener::raise_backlog(int backlog) {
    const auto socket = svr_sock_.load();
    return socket != INVALID_SOCKET && ::listen(socket, backlog) == 0;
}

std::size_t Listener::open_connections() const {
    std::lock_guard lock(mutex_);
    return connections_.size();
}

bool Listener::process_and_close_socket(socket_t sock) {
    Connection connection(sock, limits_);
    bool registered = false;
    {
        std::lock_guard lock(mutex_);
        if (!stopping_) {
            connections_.insert(&connection);
            registered = true;
        }
    }
    t_connection = &connection;
    bool ok = registered;
    for (std::size_t served = 0; registered && served < limits_.max_requests_per_connection;
         ++served) {
        if (stopping_ || !connection.wait_for_request(limits_.idle_timeout)) break;
        connection.begin_request();
        const bool last = served + 1 == limits_.max_requests_per_connection || stopping_;
        bool closed = false;
        // Parsed ranges are dropped before anything answers: no route serves partial content.
        ok = process_request(connection, last, closed,
                             [](httplib::Request& request) { request.ranges.clear(); });
        if (connection.refusal() != Refusal::none) {
            if (connection.written() == 0) write_refusal(connection, connection.refusal());
            break;
        }
        connection.end_request();
        if (!ok || closed || last || connection.close_requested()) break;
    }
    t_connection = nullptr;
    {
        std::lock_guard lock(mutex_);
        connections_.erase(&connection);
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return ok;
}

void Listener::write_refusal(Connection& connection, Refusal refusal) {
    httplib::Response response;
    response.status = 400;
    if (render_refusal_) render_refusal_(refusal, response);
    std::string head = "HTTP/1.1 " + std::to_string(response.status) + " " +
                       reason_phrase(response.status) + "\r\n";
    for (const auto& [name, value] : response.headers) head += name + ": " + value + "\r\n";
    head +=
        "Content-Length: " + std::to_string(response.body.size()) + "\r\nConnection: close\r\n\r\n";
    if (connection.write(head.data(), head.size()) >= 0 && !response.body.empty()) {
        connection.write(response.body.data(), response.body.size());
    }
    if (log_) {
        httplib::Request request;
        connection.get_remote_ip_and_port(request.remote_addr, request.remote_port);
        log_(request, response);
    }
}

void Listener::stop_within(std::chrono::milliseconds grace) {
    if (stopping_.exchange(true)) return;
    httplib::Server::stop();
    const auto shut_down = [this](bool all) {
        std::lock_guard lock(mutex_);
        for (Connection* connection : connections_) {
            const auto phase = connection->phase();
            if (all || phase == Connection::Phase::idle || phase == Connection::Phase::headers) {
                connection->shut_down();
            }
        }
    };
    // Nobody waits for an idle connection or a request that has not fully arrived.
    shut_down(false);
    const auto until = Clock::now() + grace;
    while (Clock::now() < until) {
        {
            std::lock_guard lock(mutex_);
            if (connections_.empty()) return;
        }
        shut_down(false);  // connections that went idle after their answer
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    shut_down(true);
}

}  // namespace rollgap::service::http
