#pragma once
// A port on 127.0.0.1 for a server a test starts (PostgreSQL, nginx, a `rollgap serve`
// process): shared by support/postgres.h and support/http_test.h, which tests include together.

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace rollgap::test {

// A port no one listens on now (the OS picks it, then it is released; there is a small window
// before the server binds it), or 0 if the OS gave none.
inline int free_loopback_port() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) return 0;
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = 0;
    socklen_t length = sizeof address;
    int port = 0;
    if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
        port = ntohs(address.sin_port);
    }
    ::close(fd);
    return port;
}

}  // namespace rollgap::test
