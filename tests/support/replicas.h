#pragma once
// Replicas for the multi-process tests (test_replicas.cpp): a throw-away PostgreSQL 15
// (support/postgres.h), N real `rollgap serve` processes (the built program, build/rollgap next
// to build/tests) sharing it as their job store, and nginx in front of them with the product's
// deploy/nginx/rollgap.conf whose one upstream server becomes one line per replica (plain
// round-robin, nothing else changed). Everything listens on 127.0.0.1 on ports from the OS; the
// destructors kill the processes and remove the temporary directories, also when a check fails
// (and a replica dies with the test runner: PR_SET_PDEATHSIG).

#include <fcntl.h>
#include <grp.h>
#include <pwd.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "support/http_test.h"
#include "support/nginx.h"
#include "support/postgres.h"
#include "support/program.h"

namespace rollgap::test {

// A fresh directory under /tmp, removed with its contents on destruction.
class TempDir {
public:
    explicit TempDir(const std::string& prefix) {
        std::string pattern = "/tmp/" + prefix + "-XXXXXX";
        REQUIRE(::mkdtemp(pattern.data()) != nullptr);
        path_ = pattern;
        // nginx's workers (`nobody` when the tests run as root) write temporary files under it.
        std::filesystem::permissions(
            path_, std::filesystem::perms::owner_all | std::filesystem::perms::group_read |
                       std::filesystem::perms::group_exec | std::filesystem::perms::others_read |
                       std::filesystem::perms::others_exec);
    }
    ~TempDir() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

// Waits up to `timeout` for `pid` to exit; its wait status, or nullopt if it still runs.
inline std::optional<int> wait_exit(pid_t pid, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        int status = 0;
        if (::waitpid(pid, &status, WNOHANG) == pid) return status;
        if (std::chrono::steady_clock::now() >= until) return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
}

// The settings of one replica beyond its store: small leases and chunks so that tests are quick.
struct ReplicaOptions {
    std::chrono::milliseconds lease{1500};
    int chunk_points = 10;
    int workers = 2;
    std::vector<std::string> extra;  // more `rollgap serve` arguments
    // More environment variables ("NAME=value"): settings a program of another build, which
    // may not know them, ignores (a flag it does not know stops it).
    std::vector<std::string> environment;
    std::string user;  // run as this user (the tests run as root), e.g. "nobody"; empty: ours
};

// One `rollgap serve` process on 127.0.0.1 (public and admin ports from the OS), its stdout and
// stderr in `log_path`.
class Replica {
public:
    Replica(const std::string& instance, const std::string& store,
            const std::filesystem::path& directory, const ReplicaOptions& options = {})
        : instance_(instance), log_path_(directory / (instance + ".log")) {
        const std::filesystem::path program = rollgap_program();
        REQUIRE_MESSAGE(std::filesystem::exists(program),
                        "no " << program.string() << " (build the rollgap target)");
        const std::filesystem::path data_dir = directory / (instance + "-data");
        std::vector<std::string> args = {program.string(),
                                         "serve",
                                         "--bind",
                                         "127.0.0.1",
                                         "--port",
                                         "0",
                                         "--admin-port",
                                         "0",
                                         "--instance",
                                         instance,
                                         "--store",
                                         store,
                                         "--data-dir",
                                         data_dir.string(),
                                         "--lease-ms",
                                         std::to_string(options.lease.count()),
                                         "--chunk-points",
                                         std::to_string(options.chunk_points),
                                         "--workers",
                                         std::to_string(options.workers),
                                         "--io-threads",
                                         "32",
                                         "--queue-length",
                                         "8",
                                         "--drain-timeout-ms",
                                         "5000",
                                         "--log-level",
                                         "info"};
        args.insert(args.end(), options.extra.begin(), options.extra.end());
        // Everything the child needs is built before fork: between fork and exec only
        // async-signal-safe calls (the runner has threads).
        std::vector<char*> argv;
        for (std::string& arg : args) argv.push_back(arg.data());
        argv.push_back(nullptr);
        std::vector<std::string> environment = options.environment;
        for (char** variable = environ; *variable != nullptr; ++variable)
            environment.emplace_back(*variable);
        std::vector<char*> envp;
        for (std::string& variable : environment) envp.push_back(variable.data());
        envp.push_back(nullptr);
        uid_t uid = 0;
        gid_t gid = 0;
        if (!options.user.empty()) {
            const passwd* account = ::getpwnam(options.user.c_str());
            REQUIRE_MESSAGE(account != nullptr, "no user " << options.user);
            uid = account->pw_uid;
            gid = account->pw_gid;
        }
        const std::string log = log_path_.string();
        const pid_t parent = ::getpid();
        pid_ = ::fork();
        REQUIRE(pid_ >= 0);
        if (pid_ == 0) {
            ::prctl(PR_SET_PDEATHSIG, SIGKILL);
            if (::getppid() != parent) ::_exit(127);
            const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
            if (fd >= 0) {
                ::dup2(fd, STDOUT_FILENO);
                ::dup2(fd, STDERR_FILENO);
            }
            if (uid != 0 &&
                (::setgroups(0, nullptr) != 0 || ::setgid(gid) != 0 || ::setuid(uid) != 0))
                ::_exit(126);
            ::execve(argv[0], argv.data(), envp.data());
            ::_exit(127);
        }
        // The start-up line names both ports: "msg=listening ... address=127.0.0.1:P
        // admin_address=127.0.0.1:Q ...".
        const bool listening = eventually(
            [&] {
                const std::string text = log_text();
                const std::size_t line = text.find("msg=listening");
                if (line == std::string::npos) return false;
                port_ = port_after(text, line, " address=127.0.0.1:");
                admin_port_ = port_after(text, line, " admin_address=127.0.0.1:");
                return port_ > 0 && admin_port_ > 0;
            },
            std::chrono::seconds(20));
        if (!listening) {
            const std::string log_so_far = log_text();
            kill9();  // the destructor does not run when the constructor fails
            FAIL("replica " << instance << " did not start: " << log_so_far);
        }
    }
    ~Replica() { kill9(); }
    Replica(const Replica&) = delete;
    Replica& operator=(const Replica&) = delete;

    const std::string& instance() const { return instance_; }
    int port() const { return port_; }
    int admin_port() const { return admin_port_; }
    pid_t pid() const { return pid_; }
    bool running() const { return pid_ > 0; }

    httplib::Client client(int read_timeout_s = 60) const {
        httplib::Client client("127.0.0.1", port_);
        client.set_connection_timeout(2, 0);
        client.set_read_timeout(read_timeout_s, 0);
        return client;
    }

    std::string log_text() const { return read_text_file(log_path_); }

    // SIGKILL: the replica dies at once, holding whatever leases it held.
    void kill9() {
        if (pid_ <= 0) return;
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, nullptr, 0);
        pid_ = -1;
    }

    // SIGTERM and the wait for the drain; the exit status, or nullopt if it had to be killed.
    std::optional<int> terminate(std::chrono::milliseconds timeout = std::chrono::seconds(15)) {
        if (pid_ <= 0) return std::nullopt;
        ::kill(pid_, SIGTERM);
        const std::optional<int> status = wait_exit(pid_, timeout);
        if (status) {
            pid_ = -1;
            return status;
        }
        kill9();
        return std::nullopt;
    }

    // The public port's /metrics.
    std::string metrics() const {
        httplib::Client c = client(10);
        const auto result = c.Get("/metrics");
        return result && result->status == 200 ? result->body : std::string();
    }

private:
    static int port_after(const std::string& text, std::size_t from, const std::string& key) {
        const std::size_t at = text.find(key, from);
        if (at == std::string::npos) return 0;
        try {
            return std::stoi(text.substr(at + key.size(), 6));
        } catch (const std::exception&) {
            return 0;
        }
    }

    std::string instance_;
    std::filesystem::path log_path_;
    pid_t pid_ = -1;
    int port_ = 0;
    int admin_port_ = 0;
};

// The sum of the samples of `name` in a Prometheus text exposition whose labels contain
// `label` (e.g. `state="running"`; empty: every sample), or nullopt when there is none.
inline std::optional<double> metric_value(const std::string& exposition, const std::string& name,
                                          const std::string& label = "") {
    std::istringstream lines(exposition);
    std::string line;
    std::optional<double> sum;
    while (std::getline(lines, line)) {
        if (line.rfind(name, 0) != 0 || line.size() <= name.size()) continue;
        const char next = line[name.size()];
        if (next != ' ' && next != '{') continue;
        if (!label.empty() && line.find(label) == std::string::npos) continue;
        const std::size_t space = line.rfind(' ');
        try {
            sum = sum.value_or(0.0) + std::stod(line.substr(space + 1));
        } catch (const std::exception&) {
        }
    }
    return sum;
}

// deploy/nginx/rollgap.conf as the product ships it, listening on 127.0.0.1:listen_port, its one
// upstream server line repeated for each of `service_ports` (same parameters; nginx's default
// balancing, plain round-robin).
inline std::string product_proxy_config(int listen_port, const std::vector<int>& service_ports) {
    REQUIRE(!service_ports.empty());
    std::string text = product_proxy_config(listen_port, service_ports.front());
    const std::string first = "server 127.0.0.1:" + std::to_string(service_ports.front()) + " ";
    const std::size_t at = text.find(first);
    REQUIRE(at != std::string::npos);
    const std::size_t line_start = text.rfind('\n', at) + 1;
    const std::size_t line_end = text.find('\n', at) + 1;
    const std::string line = text.substr(line_start, line_end - line_start);
    std::string more;
    for (std::size_t i = 1; i < service_ports.size(); ++i) {
        more +=
            replace_once(line, first, "server 127.0.0.1:" + std::to_string(service_ports[i]) + " ");
    }
    return text.insert(line_end, more);
}

// What `command` (a shell command line) prints on stdout; it must exit 0.
inline std::string command_output(const std::string& command) {
    FILE* pipe = ::popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    std::string output;
    char buffer[65536];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
        output.append(buffer, n);
    const int status = ::pclose(pipe);
    CAPTURE(command);
    CAPTURE(output.substr(0, 2000));
    REQUIRE(status == 0);
    return output;
}

// The rows `sql` selects in database `database` of `server`, unaligned ("a|b" lines), read with
// psql over loopback (trust authentication).
inline std::string psql(const PostgresServer& server, const std::string& database,
                        const std::string& sql) {
    return command_output(std::string(postgres_bin) + "/psql -h 127.0.0.1 -p " +
                          std::to_string(server.port()) + " -U postgres -d " + database +
                          " -At -c \"" + sql + "\"");
}

// PostgreSQL, `count` replicas sharing one fresh database of it, and optionally nginx in front.
class ReplicaSet {
public:
    explicit ReplicaSet(int count, const ReplicaOptions& options = {}, bool with_proxy = false)
        : directory_("rollgap-replicas") {
        REQUIRE_MESSAGE(postgres_.running(), postgres_.error());
        dsn_ = postgres_.create_database("replicas");
        REQUIRE(!dsn_.empty());
        for (int i = 0; i < count; ++i) add(std::string(1, static_cast<char>('a' + i)), options);
        if (with_proxy) start_proxy();
    }

    Replica& add(const std::string& instance, const ReplicaOptions& options = {}) {
        replicas_.push_back(std::make_unique<Replica>(instance, dsn_, directory_.path(), options));
        return *replicas_.back();
    }

    void start_proxy() {
        REQUIRE_MESSAGE(nginx_installed(), "nginx is not installed (scripts/install-deps.sh)");
        std::vector<int> ports;
        for (const auto& replica : replicas_) ports.push_back(replica->port());
        proxy_port_ = free_loopback_port();
        REQUIRE(proxy_port_ > 0);
        nginx_ = std::make_unique<Nginx>(directory_.path() / "nginx",
                                         product_proxy_config(proxy_port_, ports));
        httplib::Client probe = proxy_client();
        const bool up = eventually([&] {
            const auto result = probe.Get("/readyz");
            return result && result->status == 200;
        });
        CAPTURE(nginx_->error_log());
        REQUIRE(up);
    }

    Replica& operator[](std::size_t i) { return *replicas_.at(i); }
    int proxy_port() const { return proxy_port_; }
    std::size_t size() const { return replicas_.size(); }
    PostgresServer& postgres() { return postgres_; }
    const std::string& dsn() const { return dsn_; }
    const std::filesystem::path& directory() const { return directory_.path(); }

    httplib::Client proxy_client(int read_timeout_s = 60) const {
        httplib::Client client("127.0.0.1", proxy_port_);
        client.set_connection_timeout(2, 0);
        client.set_read_timeout(read_timeout_s, 0);
        return client;
    }

    // The end of every replica's log, for a failing check's context.
    std::string logs(std::size_t tail_bytes = 4000) const {
        std::string text;
        for (const auto& replica : replicas_) {
            const std::string log = replica->log_text();
            text += "---- " + replica->instance() + " (last lines)\n" +
                    log.substr(log.size() > tail_bytes ? log.size() - tail_bytes : 0);
        }
        return text;
    }

private:
    // Declared first, destroyed last: the replicas and nginx are gone before their directory.
    TempDir directory_;
    PostgresServer postgres_;
    std::string dsn_;
    std::vector<std::unique_ptr<Replica>> replicas_;
    int proxy_port_ = 0;
    std::unique_ptr<Nginx> nginx_;
};

}  // namespace rollgap::test
