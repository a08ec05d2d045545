// The container image's single-container mode (deploy/container/entrypoint.sh, the image's
// /usr/local/bin/rollgap-container, default command `proxied`): run here outside an image with
// this build's rollgap, Debian's nginx and the product's deploy/nginx/rollgap.conf. What the
// README's `docker run -p 8080:8080` publishes must be nginx, never the service: the service
// listens on loopback only, the proxy answers, a signal stops both cleanly, the death of
// either stops the other with a failure status, and a public ROLLGAP_BIND is refused.

#include <signal.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <doctest/doctest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/http_test.h"
#include "support/loopback_port.h"
#include "support/nginx.h"
#include "support/program.h"
#include "support/repository.h"

using namespace rollgap::test;
using namespace std::chrono_literals;

namespace container_entrypoint_test {

// The listening sockets of /proc/net/tcp{,6} on `port`: their local addresses as the kernel
// writes them (0100007F = 127.0.0.1, 00000000 = every IPv4 interface, ...).
std::vector<std::string> listeners(int port) {
    std::vector<std::string> found;
    char hex_port[8];
    std::snprintf(hex_port, sizeof hex_port, "%04X", port);
    for (const char* table : {"/proc/net/tcp", "/proc/net/tcp6"}) {
        std::ifstream file(table);
        std::string line;
        std::getline(file, line);  // the header
        while (std::getline(file, line)) {
            std::istringstream fields(line);
            std::string slot, local, remote, state;
            fields >> slot >> local >> remote >> state;
            const auto colon = local.rfind(':');
            if (state == "0A" && colon != std::string::npos && local.substr(colon + 1) == hex_port)
                found.push_back(local.substr(0, colon));
        }
    }
    return found;
}

// bash deploy/container/entrypoint.sh ARGS with the image's paths replaced by this build's,
// in a process group of its own (so a failed test can stop whatever the script started).
class Container {
public:
    Container(const std::vector<std::string>& arguments, std::vector<std::string> environment)
        : directory_(fresh_temp_dir()) {
        REQUIRE_MESSAGE(nginx_installed(),
                        "no " << nginx_binary << " (scripts/install-deps.sh installs it)");
        proxy_port_ = free_loopback_port();
        service_port_ = free_loopback_port();
        admin_port_ = free_loopback_port();
        const std::filesystem::path& prefix = prefix_ = std::filesystem::path(directory_) / "nginx";
        std::filesystem::create_directories(prefix);
        // nginx's workers run as nobody when the tests run as root: they use its directories.
        std::filesystem::permissions(directory_, std::filesystem::perms(0755));
        std::filesystem::permissions(prefix, std::filesystem::perms(0755));
        const std::vector<std::string> settings = {
            "ROLLGAP_BINARY=" + rollgap_program().string(),
            "ROLLGAP_NGINX_BINARY=" + std::string(nginx_binary),
            "ROLLGAP_NGINX_CONF=" + (repository_root() / "deploy/nginx/rollgap.conf").string(),
            "ROLLGAP_NGINX_PREFIX=" + prefix.string(),
            "ROLLGAP_PROXY_LISTEN=127.0.0.1:" + std::to_string(proxy_port_),
            "ROLLGAP_SERVICE_PORT=" + std::to_string(service_port_),
            "ROLLGAP_ADMIN_PORT=" + std::to_string(admin_port_),
            "ROLLGAP_DATA_DIR=" + directory_ + "/data",
            "ROLLGAP_DRAIN_TIMEOUT_MS=5000",
            "PATH=/usr/local/bin:/usr/bin:/bin"};
        environment.insert(environment.begin(), settings.begin(), settings.end());
        std::vector<std::string> args = {
            "/bin/bash", (repository_root() / "deploy/container/entrypoint.sh").string()};
        args.insert(args.end(), arguments.begin(), arguments.end());
        // Built before fork: between fork and exec only async-signal-safe calls.
        std::vector<char*> argv;
        for (std::string& arg : args) argv.push_back(arg.data());
        argv.push_back(nullptr);
        std::vector<char*> envp;
        for (std::string& variable : environment) envp.push_back(variable.data());
        envp.push_back(nullptr);
        const std::string log = log_path();
        pid_ = ::fork();
        REQUIRE(pid_ >= 0);
        if (pid_ == 0) {
            ::setpgid(0, 0);
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            if (fd >= 0) {
                ::dup2(fd, STDOUT_FILENO);
                ::dup2(fd, STDERR_FILENO);
            }
            ::execve(argv[0], argv.data(), envp.data());
            ::_exit(127);
        }
        ::setpgid(pid_, pid_);
    }
    ~Container() {
        // nginx has a process group of its own (its pid file names its leader)
        const std::string nginx = read_text_file(prefix_ / "nginx.pid");
        if (const int leader = std::atoi(nginx.c_str()); leader > 0) ::kill(-leader, SIGKILL);
        if (pid_ > 0) {
            ::kill(-pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
        ::kill(-pid_, SIGKILL);  // a rollgap left behind
    }
    Container(const Container&) = delete;
    Container& operator=(const Container&) = delete;

    int proxy_port() const { return proxy_port_; }
    int service_port() const { return service_port_; }
    int admin_port() const { return admin_port_; }
    pid_t pid() const { return pid_; }
    std::string log_path() const { return directory_ + "/container.log"; }
    std::string log_text() const { return read_text_file(log_path()); }

    // The exit status once the script has ended within `timeout`, else nothing.
    std::optional<int> exit_status(std::chrono::milliseconds timeout) {
        std::optional<int> status;
        eventually(
            [&] {
                int raw = 0;
                if (::waitpid(pid_, &raw, WNOHANG) != pid_) return false;
                status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
                pid_ = -pid_;  // reaped: the group id stays for the destructor's sweep
                return true;
            },
            timeout);
        return status;
    }

    // The process the script started whose command line contains `needle` (its child: nginx
    // runs in a process group of its own).
    pid_t child(const std::string& needle) const {
        for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
            const std::string name = entry.path().filename().string();
            if (name.find_first_not_of("0123456789") != std::string::npos) continue;
            const pid_t pid = std::stoi(name);
            // /proc/PID/stat: "pid (comm) state ppid ..."; comm may hold spaces, not ')'
            const std::string stat = read_text_file(entry.path() / "stat");
            const auto close = stat.rfind(')');
            if (close == std::string::npos) continue;
            std::istringstream fields(stat.substr(close + 1));
            std::string state;
            pid_t parent = 0;
            fields >> state >> parent;
            if (parent != pid_) continue;
            std::string command = read_text_file(entry.path() / "cmdline");
            for (char& c : command)
                if (c == '\0') c = ' ';
            if (command.find(needle) != std::string::npos) return pid;
        }
        return 0;
    }

private:
    std::string directory_;
    std::filesystem::path prefix_;
    int proxy_port_ = 0;
    int service_port_ = 0;
    int admin_port_ = 0;
    pid_t pid_ = 0;
};

int status_of(int port, const std::string& path, std::string* server = nullptr) {
    httplib::Client client("127.0.0.1", port);
    client.set_connection_timeout(1, 0);
    client.set_read_timeout(30, 0);
    const auto result = client.Get(path);
    if (!result) return 0;
    if (server != nullptr) *server = result->get_header_value("Server");
    return result->status;
}

}  // namespace container_entrypoint_test

namespace cet = container_entrypoint_test;

TEST_CASE(
    "container entrypoint: proxied, nginx answers on the published port, the service listens on "
    "loopback only, and SIGTERM stops both with exit 0") {
    cet::Container container({"proxied"}, {});
    CAPTURE(container.log_text());
    std::string server;
    REQUIRE(eventually(
        [&] { return cet::status_of(container.proxy_port(), "/readyz", &server) == 200; }, 20s));
    CHECK(server == "nginx");  // the answer came through the proxy

    httplib::Client client("127.0.0.1", container.proxy_port());
    client.set_read_timeout(60, 0);
    const auto answer =
        post_json(client, "/v1/roll-gap", {{"options", {{"distributions", false}}}});
    REQUIRE(answer);
    CHECK(answer->status == 200);
    CHECK(body_json(answer)["result"]["status"] == "ok");
    // The access log is the proxy's (rollgap.conf's format), the request log the service's.
    CHECK(eventually([&] {
        const std::string log = container.log_text();
        return log.find("proxy id=") != std::string::npos &&
               log.find("route=/v1/roll-gap") != std::string::npos;
    }));

    // The service: on 127.0.0.1 only (never every interface); the proxy on what it was told.
    const auto service = cet::listeners(container.service_port());
    REQUIRE(service.size() == 1);
    CHECK(service.front() == "0100007F");
    CHECK(cet::listeners(container.proxy_port()) == std::vector<std::string>{"0100007F"});
    // The image's HEALTHCHECK command checks the service's admin listener.
    CHECK(cet::status_of(container.admin_port(), "/livez") == 200);

    ::kill(container.pid(), SIGTERM);
    const auto status = container.exit_status(30s);
    REQUIRE(status.has_value());
    CHECK(*status == 0);
    CHECK(container.log_text().find("rollgap-container: stopped (the service's exit status 0)") !=
          std::string::npos);
    CHECK(cet::listeners(container.proxy_port()).empty());
    CHECK(cet::listeners(container.service_port()).empty());
}

TEST_CASE(
    "container entrypoint: when the service or nginx dies, the other is stopped and the "
    "container exits non-zero") {
    for (const std::string victim : {"serve", "nginx"}) {
        CAPTURE(victim);
        cet::Container container({"proxied"}, {});
        CAPTURE(container.log_text());
        REQUIRE(eventually([&] { return cet::status_of(container.proxy_port(), "/readyz") == 200; },
                           20s));
        const pid_t pid = container.child(victim == "serve" ? " serve" : "nginx: master");
        REQUIRE(pid > 0);
        ::kill(pid, SIGKILL);
        const auto status = container.exit_status(30s);
        REQUIRE(status.has_value());
        CHECK(*status != 0);
        CHECK(container.log_text().find(victim == "serve"
                                            ? "the service ended on its own"
                                            : "nginx ended on its own") != std::string::npos);
        // Nothing is left listening: no proxy in front of nothing, no unproxied service.
        CHECK(eventually([&] { return cet::listeners(container.proxy_port()).empty(); }));
        CHECK(cet::listeners(container.service_port()).empty());
    }
}

TEST_CASE(
    "container entrypoint: a public ROLLGAP_BIND is refused in the proxied mode, and any other "
    "command runs rollgap itself") {
    {
        cet::Container container({"proxied"}, {"ROLLGAP_BIND=0.0.0.0"});
        const auto status = container.exit_status(10s);
        REQUIRE(status.has_value());
        CHECK(*status == 2);
        CHECK(container.log_text().find("ROLLGAP_BIND=0.0.0.0: in the proxied mode") !=
              std::string::npos);
        CHECK(cet::listeners(container.service_port()).empty());
        CHECK(cet::listeners(container.proxy_port()).empty());
    }
    {
        cet::Container container({"--version"}, {});
        const auto status = container.exit_status(10s);
        REQUIRE(status.has_value());
        CHECK(*status == 0);
        CHECK(container.log_text().find("rollgap") == 0);
    }
}
