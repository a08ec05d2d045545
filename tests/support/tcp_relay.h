#pragma once
// A TCP relay on 127.0.0.1 for partition tests: every connection accepted on its port is
// forwarded to `target_port`; freeze() stops forwarding in both directions (and accepting), so
// the peers' sockets stay open and silent, as in a network partition; thaw() resumes. Bytes
// that arrived meanwhile are forwarded then. Threads only, no privileges.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <list>
#include <mutex>
#include <thread>

namespace rollgap::test {

class TcpRelay {
public:
    explicit TcpRelay(int target_port) : target_port_(target_port) {
        listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
        const int one = 1;
        ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        address.sin_port = 0;
        ::bind(listener_, reinterpret_cast<sockaddr*>(&address), sizeof address);
        ::listen(listener_, 64);
        socklen_t length = sizeof address;
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&address), &length);
        port_ = ntohs(address.sin_port);
        acceptor_ = std::thread([this] { accept_loop(); });
    }
    ~TcpRelay() {
        stopping_ = true;
        if (acceptor_.joinable()) acceptor_.join();
        std::lock_guard lock(mutex_);
        for (std::thread& pump : pumps_) pump.join();
        ::close(listener_);
    }
    TcpRelay(const TcpRelay&) = delete;
    TcpRelay& operator=(const TcpRelay&) = delete;

    int port() const { return port_; }
    void freeze() { frozen_ = true; }
    void thaw() { frozen_ = false; }

private:
    static bool wait_readable(int fd, int ms) {
        pollfd p{fd, POLLIN, 0};
        return ::poll(&p, 1, ms) > 0;
    }

    void accept_loop() {
        while (!stopping_) {
            if (frozen_ || !wait_readable(listener_, 20)) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            const int client = ::accept(listener_, nullptr, nullptr);
            if (client < 0) continue;
            const int server = ::socket(AF_INET, SOCK_STREAM, 0);
            sockaddr_in address{};
            address.sin_family = AF_INET;
            address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            address.sin_port = htons(static_cast<std::uint16_t>(target_port_));
            if (::connect(server, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
                ::close(client);
                ::close(server);
                continue;
            }
            std::lock_guard lock(mutex_);
            pumps_.emplace_back([this, client, server] { pump(client, server); });
        }
    }

    // Both directions of one connection; closes both sockets when either side closes.
    void pump(int a, int b) {
        char buffer[16384];
        bool open = true;
        while (open && !stopping_) {
            if (frozen_) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            pollfd fds[2] = {{a, POLLIN, 0}, {b, POLLIN, 0}};
            if (::poll(fds, 2, 20) <= 0) continue;
            for (int i = 0; i < 2 && open; ++i) {
                if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
                const int from = i == 0 ? a : b;
                const int to = i == 0 ? b : a;
                const ssize_t n = ::read(from, buffer, sizeof buffer);
                if (n <= 0) {
                    open = false;
                    break;
                }
                for (ssize_t sent = 0; sent < n;) {
                    const ssize_t w =
                        ::send(to, buffer + sent, static_cast<std::size_t>(n - sent), MSG_NOSIGNAL);
                    if (w <= 0) {
                        open = false;
                        break;
                    }
                    sent += w;
                }
            }
        }
        ::close(a);
        ::close(b);
    }

    int target_port_;
    int listener_ = -1;
    int port_ = 0;
    std::atomic<bool> frozen_{false};
    std::atomic<bool> stopping_{false};
    std::thread acceptor_;
    std::mutex mutex_;
    std::list<std::thread> pumps_;
};

}  // namespace rollgap::test
