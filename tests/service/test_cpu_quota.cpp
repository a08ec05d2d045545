// The CPU budget (service/cpu_quota.h): cgroup v2 and v1 limits read from fixture trees laid
// out like real systems, the affinity mask checked against the kernel's own account of it
// (/proc/self/status) and under `taskset -c 0`, and the service sized by it: `rollgap serve`
// under `taskset -c 0` starts one worker and says so.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <doctest/doctest.h>

#include "service/config.h"
#include "service/cpu_quota.h"

#include "support/program.h"
#include "support/repository.h"

namespace {

using rollgap::service::cgroup_cpu_limit;
using rollgap::service::cpu_budget;
using rollgap::test::rollgap_program;

const std::filesystem::path fixtures =
    rollgap::test::repository_root() / "tests" / "fixtures" / "cgroup";

std::optional<double> fixture_limit(const std::string& name) {
    const auto dir = fixtures / name;
    return cgroup_cpu_limit(dir / "cgroup", dir / "mountinfo", dir);
}

// CPUs in "Cpus_allowed_list:\t0-1,4" of /proc/self/status: the kernel's independent account.
int allowed_cpus_from_status() {
    std::ifstream status("/proc/self/status");
    int count = 0;
    for (std::string line; std::getline(status, line);) {
        if (line.rfind("Cpus_allowed_list:", 0) != 0) continue;
        std::string list = line.substr(line.find(':') + 1);
        std::size_t start = 0;
        while (start < list.size()) {
            const auto comma = list.find(',', start);
            const std::string range =
                list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
            const auto dash = range.find('-');
            const int from = std::stoi(range.substr(0, dash));
            const int to = dash == std::string::npos ? from : std::stoi(range.substr(dash + 1));
            count += to - from + 1;
            if (comma == std::string::npos) break;
            start = comma + 1;
        }
    }
    return count;
}

}  // namespace

TEST_CASE("cpu quota: cgroup v2 cpu.max and v1 cfs quota/period parse") {
    using rollgap::service::parse_cfs_quota;
    using rollgap::service::parse_cpu_max;
    CHECK(parse_cpu_max("200000 100000\n") == 2.0);
    CHECK(parse_cpu_max("50000 100000") == 0.5);
    CHECK_FALSE(parse_cpu_max("max 100000\n"));
    CHECK_FALSE(parse_cpu_max(""));
    CHECK_FALSE(parse_cpu_max("abc 100000"));
    CHECK_FALSE(parse_cpu_max("100000 0"));
    CHECK(parse_cfs_quota("150000\n", "100000\n") == 1.5);
    CHECK_FALSE(parse_cfs_quota("-1", "100000"));
    CHECK_FALSE(parse_cfs_quota("", "100000"));
}

TEST_CASE("cpu quota: the tightest limit from the process's group up to the mount") {
    // v2: the pod's 1.5 CPUs bind although the container itself says max and the parent 4.
    CHECK(fixture_limit("v2-nested") == 1.5);
    // v2 in a container whose cgroup namespace shows its own group as the mount's root.
    CHECK(fixture_limit("v2-container") == 2.0);
    // v1: cpu,cpuacct hierarchy found through mountinfo; the group's 0.5 binds, the parent is
    // unlimited.
    CHECK(fixture_limit("v1-quota") == 0.5);
    // v1 without a quota (this machine's layout).
    CHECK_FALSE(fixture_limit("v1-unlimited"));
    CHECK_FALSE(cgroup_cpu_limit(fixtures / "missing" / "cgroup",
                                 fixtures / "missing" / "mountinfo", fixtures));

    const auto budget = cpu_budget(fixtures / "v1-quota" / "cgroup",
                                   fixtures / "v1-quota" / "mountinfo", fixtures / "v1-quota");
    CHECK(budget.effective == 1);  // half a CPU still needs one thread
}

TEST_CASE("cpu quota: affinity mask as the kernel reports it") {
    const auto affinity = rollgap::service::affinity_cpu_count();
    REQUIRE(affinity);
    CHECK(*affinity == allowed_cpus_from_status());
    const auto budget = cpu_budget();
    CHECK(budget.effective <= *affinity);
    CHECK(budget.effective >= 1);
    if (const char* expected = std::getenv("ROLLGAP_EXPECT_AFFINITY")) {
        CHECK(*affinity == std::atoi(expected));
        CHECK(budget.effective == std::atoi(expected));
    }
}

TEST_CASE("cpu quota: under taskset -c 0 the budget is one CPU") {
    if (std::getenv("ROLLGAP_EXPECT_AFFINITY") != nullptr) return;  // the child run below
    const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
    const std::string command =
        "ROLLGAP_EXPECT_AFFINITY=1 taskset -c 0 " + self +
        " -tc='cpu quota: affinity mask as the kernel reports it' >/dev/null 2>&1";
    CHECK(std::system(command.c_str()) == 0);
    // The check is real: claiming two CPUs under taskset -c 0 fails.
    const std::string wrong =
        "ROLLGAP_EXPECT_AFFINITY=2 taskset -c 0 " + self +
        " -tc='cpu quota: affinity mask as the kernel reports it' >/dev/null 2>&1";
    CHECK(std::system(wrong.c_str()) != 0);
}

TEST_CASE("cpu quota: the service's workers and analysis budget default to the CPU budget") {
    using rollgap::service::ServerConfig;
    const int cpus = cpu_budget().effective;
    const ServerConfig resolved = ServerConfig{}.resolved();
    CHECK(resolved.workers == static_cast<std::size_t>(cpus));
    CHECK(resolved.analysis_threads == resolved.workers);
    CHECK(rollgap::service::describe(resolved).find(" cpus=" + std::to_string(cpus) + " ") !=
          std::string::npos);
    // Given values win; an analysis never spreads over more workers than there are.
    ServerConfig given;
    given.workers = 3;
    given.analysis_threads = 8;
    CHECK(given.resolved().workers == 3);
    CHECK(given.resolved().analysis_threads == 3);
}

TEST_CASE("cpu quota: `taskset -c 0 rollgap serve` starts one worker and logs it") {
    const std::filesystem::path program = rollgap_program();
    const std::filesystem::path log = std::filesystem::temp_directory_path() /
                                      ("rollgap-taskset-" + std::to_string(::getpid()) + ".log");
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
        std::FILE* out = std::freopen(log.c_str(), "w", stdout);
        if (out == nullptr) ::_exit(126);
        ::dup2(::fileno(stdout), STDERR_FILENO);
        ::unsetenv("ROLLGAP_WORKERS");
        ::unsetenv("ROLLGAP_ANALYSIS_THREADS");
        ::execlp("taskset", "taskset", "-c", "0", program.c_str(), "serve", "--port", "0",
                 "--admin-port", "0", "--io-threads", "4", "--log-level", "info",
                 static_cast<char*>(nullptr));
        ::_exit(127);
    }
    std::string line;
    for (int attempt = 0; attempt < 200 && line.empty(); ++attempt) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        std::ifstream file(log);
        for (std::string text; std::getline(file, text);) {
            if (text.find("msg=listening") != std::string::npos) line = text;
        }
    }
    ::kill(child, SIGTERM);
    int status = 0;
    ::waitpid(child, &status, 0);
    std::filesystem::remove(log);
    CAPTURE(line);
    REQUIRE_FALSE(line.empty());
    CHECK(line.find(" workers=1 ") != std::string::npos);
    CHECK(line.find(" analysis_threads=1 ") != std::string::npos);
    CHECK(line.find(" cpus=1 ") != std::string::npos);
    CHECK(line.find(" cpu_affinity=1 ") != std::string::npos);
}
