#pragma once
// nginx for the HTTP tests (test_http_nginx.cpp, test_http_front_proxy.cpp): Debian's
// /usr/sbin/nginx run in the foreground with every file under one directory, and the
// repository's front proxy configuration (deploy/nginx/rollgap.conf) with only its two
// addresses set for a test. Only 127.0.0.1 is ever listened on.

#include <signal.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include <doctest/doctest.h>

#include "support/repository.h"

namespace rollgap::test {

inline const char* const nginx_binary = "/usr/sbin/nginx";

inline bool nginx_installed() { return std::filesystem::exists(nginx_binary); }

inline std::string read_text_file(const std::filesystem::path& path) {
    std::ifstream file(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

// Replaces the one occurrence of `from` in `text` by `to`; fails the test if there is not
// exactly one, so a change to the configuration's addresses cannot silently go untested.
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    REQUIRE_MESSAGE(at != std::string::npos, "not found in the configuration: " << from);
    REQUIRE_MESSAGE(text.find(from, at + 1) == std::string::npos,
                    "more than once in the configuration: " << from);
    return text.replace(at, from.size(), to);
}

// deploy/nginx/rollgap.conf as the product ships it, listening on 127.0.0.1:listen_port in
// front of the service on 127.0.0.1:service_port. Nothing else is changed (scripts/run-proxy.sh
// makes the same two replacements).
inline std::string product_proxy_config(int listen_port, int service_port) {
    const auto path = repository_root() / "deploy" / "nginx" / "rollgap.conf";
    std::string text = read_text_file(path);
    REQUIRE_MESSAGE(!text.empty(), "cannot read " << path);
    text = replace_once(text, "\n        listen 8080;",
                        "\n        listen 127.0.0.1:" + std::to_string(listen_port) + ";");
    return replace_once(text, "server 127.0.0.1:8090 ",
                        "server 127.0.0.1:" + std::to_string(service_port) + " ");
}

// nginx in the foreground with `config` as its configuration and `directory` as its prefix
// (relative paths in the configuration, temporary files, pid). Its stdout (the access log of
// the product configuration) and stderr (its error log) go to files in the directory.
class Nginx {
public:
    Nginx(const std::filesystem::path& directory, const std::string& config)
        : directory_(directory) {
        std::filesystem::create_directories(directory_);
        {
            std::ofstream file(directory_ / "nginx.conf");
            file << config;
        }
        const std::string prefix = directory_.string() + "/";
        const std::string conf_path = (directory_ / "nginx.conf").string();
        const std::string stdout_path = (directory_ / "stdout.log").string();
        const std::string stderr_path = (directory_ / "stderr.log").string();
        pid_ = ::fork();
        REQUIRE(pid_ >= 0);
        if (pid_ == 0) {
            const int out = ::open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            const int err = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            if (out >= 0) ::dup2(out, STDOUT_FILENO);
            if (err >= 0) ::dup2(err, STDERR_FILENO);
            // -e: the error log until the configuration names one (the compiled-in default is
            // /var/log/nginx, which need not be writable).
            ::execl(nginx_binary, "nginx", "-p", prefix.c_str(), "-c", conf_path.c_str(), "-e",
                    "stderr", static_cast<char*>(nullptr));
            ::_exit(127);
        }
    }
    Nginx(const Nginx&) = delete;
    Nginx& operator=(const Nginx&) = delete;

    ~Nginx() {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            int status = 0;
            for (int i = 0; i < 300 && ::waitpid(pid_, &status, WNOHANG) != pid_; ++i) {
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
                if (i == 299) {
                    ::kill(pid_, SIGKILL);
                    ::waitpid(pid_, &status, 0);
                }
            }
        }
        std::error_code ignored;
        std::filesystem::remove_all(directory_, ignored);
    }

    // The error log (stderr, and error.log when a configuration names it).
    std::string error_log() const {
        return read_text_file(directory_ / "stderr.log") + read_text_file(directory_ / "error.log");
    }
    std::string access_log() const { return read_text_file(directory_ / "stdout.log"); }

    pid_t master_pid() const { return pid_; }

    // The worker process (the product configuration runs one), or -1 before it started.
    pid_t worker_pid() const {
        for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
            const std::string name = entry.path().filename().string();
            if (name.find_first_not_of("0123456789") != std::string::npos) continue;
            const std::string stat = read_text_file(entry.path() / "stat");
            // "pid (comm) state ppid ...": the parent follows the closing parenthesis.
            const std::size_t close = stat.rfind(')');
            if (close == std::string::npos || close + 4 > stat.size()) continue;
            int parent = 0;
            try {
                parent = std::stoi(stat.substr(close + 4));
            } catch (const std::exception&) {
                continue;
            }
            if (parent == pid_) return static_cast<pid_t>(std::stoi(name));
        }
        return -1;
    }

private:
    std::filesystem::path directory_;
    pid_t pid_ = -1;
};

// Resident memory of a process in KiB (VmRSS), or -1.
inline long resident_kib(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    }
    return -1;
}

}  // namespace rollgap::test
