#pragma once
// How many CPUs this process may really use: the smallest of the cgroup CPU quota (v2
// `cpu.max`, v1 `cpu.cfs_quota_us` / `cpu.cfs_period_us`, found through /proc/self/cgroup
// and /proc/self/mountinfo, the tightest limit on the path from the process's group up to the
// mount), the affinity mask (`taskset`, cpusets) and the hardware. hardware_concurrency()
// sees only the last, so a pod limited to 2 CPUs on a 64-core node would start 64 threads.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace rollgap::service {

// `cpu.max` text ("max 100000", "150000 100000"): CPUs allowed, nothing when unlimited or
// malformed.
std::optional<double> parse_cpu_max(std::string_view text);
// cgroup v1 `cpu.cfs_quota_us` and `cpu.cfs_period_us` texts (quota -1 = unlimited).
std::optional<double> parse_cfs_quota(std::string_view quota, std::string_view period);

// The cgroup CPU limit of the process described by `proc_self_cgroup` and `mountinfo`, with
// every mount point read under `root` (fixtures use a directory; the real system "/").
std::optional<double> cgroup_cpu_limit(const std::filesystem::path& proc_self_cgroup,
                                       const std::filesystem::path& mountinfo,
                                       const std::filesystem::path& root);

// CPUs in the calling thread's affinity mask, nothing if it cannot be read.
std::optional<int> affinity_cpu_count();

struct CpuBudget {
    std::optional<double> cgroup_limit;
    std::optional<int> affinity;
    int hardware = 1;
    int effective = 1;  // min(ceil(cgroup_limit), affinity, hardware), at least 1
};
CpuBudget cpu_budget(const std::filesystem::path& proc_self_cgroup = "/proc/self/cgroup",
                     const std::filesystem::path& mountinfo = "/proc/self/mountinfo",
                     const std::filesystem::path& root = "/");

// "cpus=2 cpu_quota=1.5 cpu_affinity=4 cpu_hardware=64" (cpu_quota=none when unlimited, and
// cpu_affinity=unknown when unreadable): for the start-up log line.
std::string describe(const CpuBudget& budget);

}  // namespace rollgap::service
