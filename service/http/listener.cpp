#include "service/http/listener.h"

#include <arpa/inet.h>
#include <limits.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
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

bool named_header(std::string_view line, std::string_view lower_case_name) {
    if (line.size() <= lower_case_name.size() || line[lower_case_name.size()] != ':') return false;
    return std::equal(
        lower_case_name.begin(), lower_case_name.end(), line.begin(),
        [](char a, char b) { return a == std::tolower(static_cast<unsigned char>(b)); });
}

}  // namespace

std::string one_connection_header(std::string_view head) {
    if (!head.starts_with("HTTP/")) return std::string(head);
    const auto says_close = [](std::string_view line) {
        if (!named_header(line, "connection")) return false;
        std::string value(line.substr(line.find(':') + 1));
        std::transform(value.begin(), value.end(), value.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        return value.find("close") != std::string::npos;
    };
    bool closing = false;
    for (std::size_t at = 0; at < head.size();) {
        const std::size_t end = head.find("\r\n", at);
        if (end == std::string_view::npos || end == at) break;
        closing = closing || says_close(head.substr(at, end - at));
        at = end + 2;
    }
    if (!closing) return std::string(head);
    std::string out;
    out.reserve(head.size());
    bool connection_written = false;
    std::size_t at = 0;
    for (;;) {
        const std::size_t end = head.find("\r\n", at);
        if (end == std::string_view::npos || end == at) break;  // the blank line, or no end
        const std::string_view line = head.substr(at, end - at);
        at = end + 2;
        if (named_header(line, "keep-alive")) continue;
        if (named_header(line, "connection")) {
            if (connection_written) continue;
            connection_written = true;
            out += "Connection: close\r\n";
            continue;
        }
        out.append(line).append("\r\n");
    }
    out.append(head.substr(at));
    return out;
}

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
        line_.clear();
        handed_ = 0;
        content_length_.reset();
        chunked_ = false;
        body_read_ = 0;
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
    void restart_write_deadline() { write_deadline_ = Clock::now() + limits_.write_deadline; }
    bool close_requested() const { return close_requested_; }
    void shut_down() { ::shutdown(fd_, SHUT_RDWR); }

    // Whether the request's body may not have been read to its end: the connection cannot carry
    // another request, and closing it must not reset the answer.
    bool body_unread() const {
        if (phase_ == Phase::headers) return false;  // refused before its body
        // A chunked body has at least its last chunk; one that was read in part ends in an
        // answer marked Connection: close (the handler's refusal).
        if (chunked_) return body_read_ == 0;
        return content_length_ && body_read_ < *content_length_;
    }
    // Whether the client may still be sending: bytes of it wait here or in the socket.
    bool input_pending() const { return begin_ < end_ || wait_for(fd_, POLLIN, 0) > 0; }

    bool is_readable() const override {
        return begin_ < end_ || wait_for(fd_, POLLIN, milliseconds_left(read_deadline_)) > 0;
    }
    // Only whether a write can proceed: a client that half-closed its side still reads.
    bool is_writable() const override { return wait_for(fd_, POLLOUT, 0) > 0; }

    ssize_t read(char* data, std::size_t size) override {
        if (refusal_ != Refusal::none) return -1;
        writing_ = false;  // the next write starts an answer
        if (handed_ == line_.size() && phase_ == Phase::headers) {
            // httplib reads the headers one byte at a time; each line is taken whole and checked
            // before any of it is handed over (a Range line is not handed over at all), and the
            // bytes after the blank line belong to the body.
            const ssize_t taken = take_header_line();
            if (taken <= 0) return taken;
        }
        if (handed_ < line_.size()) {
            const std::size_t n = std::min(size, line_.size() - handed_);
            std::memcpy(data, line_.data() + handed_, n);
            handed_ += n;
            return static_cast<ssize_t>(n);
        }
        if (begin_ == end_) {
            const ssize_t filled = fill();
            if (filled <= 0) return filled;
        }
        const std::size_t n = std::min(size, end_ - begin_);
        std::memcpy(data, buffer_.data() + begin_, n);
        begin_ += n;
        body_read_ += n;
        return static_cast<ssize_t>(n);
    }

    ssize_t write(const char* data, std::size_t size) override {
        if (!writing_) {
            writing_ = true;
            phase_ = Phase::answering;
            write_deadline_ = Clock::now() + limits_.write_deadline;
            // httplib writes the status line and headers in one piece, adding its own
            // Connection or Keep-Alive to the handler's: one Connection: close, no Keep-Alive
            // beside it.
            const std::string head = one_connection_header({data, size});
            if (head.size() != size)
                return send_all(head.data(), head.size()) < 0 ? -1 : static_cast<ssize_t>(size);
        }
        return send_all(data, size);
    }

    ssize_t send_all(const char* data, std::size_t size) {
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

    // Reads the next header line into line_ (refusing it, dropping it if it is a Range, or
    // keeping it to be handed over); 1 once a line is ready, 0 at the peer's end of stream,
    // -1 on a refusal or error.
    ssize_t take_header_line() {
        for (;;) {
            line_.clear();
            handed_ = 0;
            for (;;) {
                if (begin_ == end_) {
                    const ssize_t filled = fill();
                    if (filled <= 0) return filled;
                }
                const char byte = buffer_[begin_];
                if (!accept_header_byte(byte)) return -1;
                ++begin_;
                line_.push_back(byte);
                if (byte == '\n') break;
            }
            if (lines_ == 1) return 1;  // the request line: httplib checks its form
            if (line_ == "\r\n") {
                if (!check_framing()) return -1;
                // Neither Content-Length nor Transfer-Encoding: the body is empty (RFC 9112
                // §6.3). httplib would read a POST's body until the peer closes, and answer
                // 408 at the read deadline: it is told the length instead.
                if (!chunked_ && !content_length_) {
                    content_length_ = 0;
                    line_ = "Content-Length: 0\r\n\r\n";
                }
                phase_ = Phase::body;
                return 1;
            }
            if (check_header_line()) return 1;
            if (refusal_ != Refusal::none) return -1;
            // A Range line: dropped, the next one is read.
        }
    }

    // The request line and each header line end in CRLF; a line that is only CRLF ends the
    // headers (httplib's rule: a bare LF does not).
    bool accept_header_byte(char byte) {
        if (++header_bytes_ > limits_.max_header_bytes) {
            refusal_ = lines_ == 0 ? Refusal::request_line_too_long : Refusal::header_too_large;
            return false;
        }
        if (lines_ == 0 && line_length_ >= limits_.max_request_line_bytes) {
            refusal_ = Refusal::request_line_too_long;
            return false;
        }
        if (byte == '\0') {
            refusal_ = Refusal::header_nul;
            return false;
        }
        if (byte == '\n') {
            ++lines_;
            if (lines_ - 1 > limits_.max_header_fields) {
                refusal_ = Refusal::too_many_header_fields;
                return false;
            }
            line_length_ = 0;
        } else {
            ++line_length_;
        }
        return true;
    }

    // A header line (in line_, with its line end): false if it is refused (refusal_ set) or
    // dropped (a Range). httplib skips a line without a colon or with a bare LF and keeps
    // whitespace before the colon in the name; a proxy may read such lines differently, so
    // they are refused. Content-Length and Transfer-Encoding are noted for check_framing().
    bool check_header_line() {
        const std::string_view line(line_);
        if (line.size() < 2 || line[line.size() - 2] != '\r')
            return refuse(Refusal::malformed_header_line);
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos || colon == 0)
            return refuse(Refusal::malformed_header_line);
        const std::string_view name = line.substr(0, colon);
        if (name.find_first_of(" \t\r") != std::string_view::npos) {
            return refuse(Refusal::malformed_header_line);
        }
        const std::string_view value = trimmed(line.substr(colon + 1, line.size() - colon - 3));
        if (named(name, "range") || named(name, "if-range")) return false;
        if (named(name, "content-length")) {
            if (content_length_) return refuse(Refusal::duplicate_content_length);
            std::uint64_t length = 0;
            const auto parsed = std::from_chars(value.data(), value.data() + value.size(), length);
            if (value.empty() || parsed.ec != std::errc() ||
                parsed.ptr != value.data() + value.size()) {
                return refuse(Refusal::invalid_content_length);
            }
            content_length_ = length;
        } else if (named(name, "transfer-encoding")) {
            if (chunked_ || value != "chunked")
                return refuse(Refusal::unsupported_transfer_encoding);
            chunked_ = true;
        }
        return true;
    }

    // At the blank line: one way to find the end of the body.
    bool check_framing() {
        if (chunked_ && content_length_)
            return refuse(Refusal::transfer_encoding_with_content_length);
        return true;
    }

    bool refuse(Refusal refusal) {
        refusal_ = refusal;
        return false;
    }

    static std::string_view trimmed(std::string_view text) {
        while (!text.empty() && (text.front() == ' ' || text.front() == '\t'))
            text.remove_prefix(1);
        while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
        return text;
    }
    static bool named(std::string_view name, std::string_view lower_case) {
        return name.size() == lower_case.size() &&
               std::equal(name.begin(), name.end(), lower_case.begin(), [](char a, char b) {
                   return std::tolower(static_cast<unsigned char>(a)) == b;
               });
    }

    int fd_;
    const ListenerLimits& limits_;
    std::array<char, 16 * 1024> buffer_{};
    std::size_t begin_ = 0, end_ = 0;

    std::atomic<Phase> phase_{Phase::idle};
    Refusal refusal_ = Refusal::none;
    std::size_t header_bytes_ = 0, lines_ = 0, line_length_ = 0;
    std::string line_;        // the header line being read or handed over
    std::size_t handed_ = 0;  // how much of line_ httplib has read
    std::optional<std::uint64_t> content_length_;
    bool chunked_ = false;
    std::uint64_t body_read_ = 0;  // bytes after the headers handed over
    Clock::time_point read_deadline_{}, write_deadline_{};
    bool writing_ = false;
    std::size_t written_ = 0;
    bool close_requested_ = false;
};

namespace {
thread_local Connection* t_connection = nullptr;
}

StackBoundedPool::StackBoundedPool(std::size_t threads, std::size_t stack_bytes) {
    pthread_attr_t attributes;
    if (::pthread_attr_init(&attributes) != 0) throw std::runtime_error("pthread_attr_init failed");
    ::pthread_attr_setstacksize(&attributes, std::max<std::size_t>(stack_bytes, PTHREAD_STACK_MIN));
    for (std::size_t i = 0; i < threads; ++i) {
        pthread_t thread{};
        if (::pthread_create(&thread, &attributes, &StackBoundedPool::run, this) != 0) break;
        threads_.push_back(thread);
    }
    ::pthread_attr_destroy(&attributes);
    if (threads > 0 && threads_.empty())
        throw std::runtime_error("cannot start connection threads");
}

StackBoundedPool::~StackBoundedPool() { shutdown(); }

void StackBoundedPool::enqueue(std::function<void()> task) {
    {
        std::lock_guard lock(mutex_);
        tasks_.push_back(std::move(task));
    }
    ready_.notify_one();
}

void StackBoundedPool::shutdown() {
    {
        std::lock_guard lock(mutex_);
        if (shutting_down_ && threads_.empty()) return;
        shutting_down_ = true;
    }
    ready_.notify_all();
    for (pthread_t thread : threads_) ::pthread_join(thread, nullptr);
    threads_.clear();
}

// As httplib's ThreadPool: the queued tasks are run to the end before the threads return.
void* StackBoundedPool::run(void* self) {
    auto& pool = *static_cast<StackBoundedPool*>(self);
    for (;;) {
        std::function<void()> task;
        {
            std::unique_lock lock(pool.mutex_);
            pool.ready_.wait(lock, [&] { return !pool.tasks_.empty() || pool.shutting_down_; });
            if (pool.tasks_.empty()) return nullptr;
            task = std::move(pool.tasks_.front());
            pool.tasks_.pop_front();
        }
        task();
    }
}

void restart_write_deadline() {
    if (t_connection != nullptr) t_connection->restart_write_deadline();
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
    bool linger = true;
    for (std::size_t served = 0; registered && served < limits_.max_requests_per_connection;
         ++served) {
        if (stopping_ || !connection.wait_for_request(limits_.idle_timeout)) break;
        connection.begin_request();
        const bool last = served + 1 == limits_.max_requests_per_connection || stopping_;
        bool closed = false;
        // The connection dropped Range lines already; whatever httplib parsed of other
        // headers into ranges is dropped too: no route serves partial content.
        ok = process_request(connection, last, closed,
                             [](httplib::Request& request) { request.ranges.clear(); });
        if (connection.refusal() != Refusal::none) {
            if (connection.written() == 0) write_refusal(connection, connection.refusal());
            // A client too slow to send its request is not waited for again.
            linger = connection.refusal() != Refusal::read_deadline;
            break;
        }
        // The rest of an unread body would be taken for the next request.
        const bool unread = connection.body_unread();
        connection.end_request();
        if (unread || !ok || closed || last || connection.close_requested()) break;
    }
    t_connection = nullptr;
    if (linger && !stopping_ && connection.input_pending()) close_gracefully(sock);
    {
        std::lock_guard lock(mutex_);
        connections_.erase(&connection);
    }
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
    return ok;
}

// Closing a socket whose receive queue holds data makes the kernel send a reset, which may
// destroy the answer before the peer has read it (nginx then answers 502 for the service's
// own 415). The answer is sent first (FIN after it), then what the client still sends is
// read and dropped until it closes, for at most limits_.linger and limits_.linger_bytes.
void Listener::close_gracefully(socket_t sock) const {
    ::shutdown(sock, SHUT_WR);
    const auto until = Clock::now() + limits_.linger;
    std::array<char, 16 * 1024> scratch{};
    std::size_t dropped = 0;
    while (dropped < limits_.linger_bytes) {
        const int left = milliseconds_left(until);
        if (left == 0 || wait_for(sock, POLLIN, left) <= 0) break;
        const ssize_t n = ::recv(sock, scratch.data(), scratch.size(), 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        dropped += static_cast<std::size_t>(n);
    }
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
