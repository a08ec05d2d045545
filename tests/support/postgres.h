#pragma once
// A throw-away PostgreSQL 15 server for tests: a fresh data directory under /tmp, loopback
// only, a free port from the OS, trust authentication. Run as the `postgres` user when the
// tests run as root (the server refuses root). Missing binaries are a failure, not a skip:
// the store's tests must run against a real server.

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/loopback_port.h"

namespace rollgap::test {

inline constexpr const char* postgres_bin = "/usr/lib/postgresql/15/bin";

class PostgresServer {
public:
    // Creates the cluster and starts it; `error()` says why when `running()` is false.
    // `max_connections`: the server's bound (tests of the service at that bound set it small).
    explicit PostgresServer(int max_connections = 200) : max_connections_(max_connections) {
        if (!std::filesystem::exists(std::string(postgres_bin) + "/initdb")) {
            error_ = std::string("PostgreSQL 15 server binaries missing in ") + postgres_bin +
                     " (apt-get install postgresql-15, see scripts/install-deps.sh)";
            return;
        }
        char pattern[] = "/tmp/rollgap-pg-XXXXXX";
        if (::mkdtemp(pattern) == nullptr) {
            error_ = "mkdtemp failed";
            return;
        }
        dir_ = pattern;
        std::filesystem::permissions(dir_, std::filesystem::perms::all);
        port_ = free_loopback_port();
        if (!run(tool("initdb") + " -D " + dir_ +
                 "/data --auth=trust -U postgres -E UTF8 --no-sync")) {
            error_ = "initdb failed (see " + dir_ + "/cmd.log)";
            return;
        }
        start();
    }
    ~PostgresServer() {
        stop();
        if (!dir_.empty()) {
            std::error_code ignored;
            std::filesystem::remove_all(dir_, ignored);
        }
    }
    PostgresServer(const PostgresServer&) = delete;
    PostgresServer& operator=(const PostgresServer&) = delete;

    bool start() {
        running_ = run(tool("pg_ctl") + " -D " + dir_ + "/data -l " + dir_ +
                       "/server.log -w -t 30 start -o \"-p " + std::to_string(port_) + " -k " +
                       dir_ + " -c listen_addresses=127.0.0.1 -c fsync=off -c max_connections=" +
                       std::to_string(max_connections_) + "\"");
        if (!running_) error_ = "pg_ctl start failed (see " + dir_ + "/server.log)";
        return running_;
    }
    // Immediate stop: what a crashed or unreachable database looks like to the service.
    bool stop() {
        if (!running_) return true;
        running_ = !run(tool("pg_ctl") + " -D " + dir_ + "/data -m immediate -w stop");
        return !running_;
    }

    // A new empty database and its DSN.
    std::string create_database(const std::string& name) const {
        if (!run(std::string(postgres_bin) + "/createdb -h 127.0.0.1 -p " + std::to_string(port_) +
                 " -U postgres " + name)) {
            return {};
        }
        return "postgresql://postgres@127.0.0.1:" + std::to_string(port_) + "/" + name;
    }

    bool running() const { return running_; }
    const std::string& error() const { return error_; }
    int port() const { return port_; }
    const std::string& directory() const { return dir_; }

private:
    std::string tool(const std::string& name) const {
        const std::string path = std::string(postgres_bin) + "/" + name;
        return ::geteuid() == 0 ? "runuser -u postgres -- " + path : path;
    }
    bool run(const std::string& command) const {
        const std::string redirected = command + " >>" + dir_ + "/cmd.log 2>&1";
        return std::system(redirected.c_str()) == 0;
    }

    std::string dir_;
    std::string error_;
    int port_ = 0;
    int max_connections_ = 200;
    bool running_ = false;
};

}  // namespace rollgap::test
