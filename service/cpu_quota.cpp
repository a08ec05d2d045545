#include "service/cpu_quota.h"

#include <sched.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace rollgap::service {
namespace {

std::optional<std::string> read_text(const std::filesystem::path& path) {
    std::ifstream file(path);
    if (!file) return std::nullopt;
    std::stringstream text;
    text << file.rdbuf();
    return text.str();
}

std::string_view trim(std::string_view text) {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string_view::npos) return {};
    return text.substr(first, text.find_last_not_of(" \t\r\n") - first + 1);
}

std::optional<long long> to_number(std::string_view text) {
    text = trim(text);
    long long value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || error != std::errc{} || end != text.data() + text.size())
        return std::nullopt;
    return value;
}

std::vector<std::string_view> split(std::string_view text, char separator) {
    std::vector<std::string_view> parts;
    for (std::size_t start = 0;;) {
        const auto at = text.find(separator, start);
        parts.push_back(
            text.substr(start, at == std::string_view::npos ? std::string_view::npos : at - start));
        if (at == std::string_view::npos) return parts;
        start = at + 1;
    }
}

std::optional<double> ratio(std::optional<long long> quota, std::optional<long long> period) {
    if (!quota || !period || *quota <= 0 || *period <= 0) return std::nullopt;
    return static_cast<double>(*quota) / static_cast<double>(*period);
}

struct Mount {
    std::string root;   // the mounted subtree of the hierarchy
    std::string point;  // where it is mounted
};

// The mount of the cgroup2 hierarchy (`v2`) or of the v1 hierarchy carrying the cpu controller.
std::optional<Mount> find_mount(const std::string& mountinfo, bool v2) {
    std::istringstream lines(mountinfo);
    for (std::string line; std::getline(lines, line);) {
        // "36 25 0:31 /root /mount/point opts [optional…] - fstype source superopts"
        const auto dash = line.find(" - ");
        if (dash == std::string::npos) continue;
        const auto head = split(std::string_view(line).substr(0, dash), ' ');
        const auto tail = split(std::string_view(line).substr(dash + 3), ' ');
        if (head.size() < 5 || tail.size() < 3) continue;
        if (v2 && tail[0] == "cgroup2") return Mount{std::string(head[3]), std::string(head[4])};
        if (!v2 && tail[0] == "cgroup") {
            const auto options = split(tail[2], ',');
            if (std::find(options.begin(), options.end(), "cpu") != options.end()) {
                return Mount{std::string(head[3]), std::string(head[4])};
            }
        }
    }
    return std::nullopt;
}

// The process's group in the hierarchy: "0::/path" (v2) or "N:cpu,cpuacct:/path" (v1).
std::optional<std::string> find_group(const std::string& proc_self_cgroup, bool v2) {
    std::istringstream lines(proc_self_cgroup);
    for (std::string line; std::getline(lines, line);) {
        const auto first = line.find(':');
        const auto second =
            first == std::string::npos ? std::string::npos : line.find(':', first + 1);
        if (second == std::string::npos) continue;
        const std::string_view controllers =
            std::string_view(line).substr(first + 1, second - first - 1);
        const std::string path = line.substr(second + 1);
        if (v2 && line.compare(0, first, "0") == 0 && controllers.empty()) return path;
        if (!v2) {
            const auto names = split(controllers, ',');
            if (std::find(names.begin(), names.end(), "cpu") != names.end()) return path;
        }
    }
    return std::nullopt;
}

// Directories from the process's group up to the mount point: a parent's limit binds too.
std::vector<std::filesystem::path> group_directories(const Mount& mount, const std::string& group,
                                                     const std::filesystem::path& root) {
    std::string relative = group;
    // Inside a container the mount's root is the container's own group: strip it.
    if (mount.root != "/" && relative.rfind(mount.root, 0) == 0)
        relative = relative.substr(mount.root.size());
    const std::filesystem::path top = root / std::filesystem::path(mount.point).relative_path();
    std::vector<std::filesystem::path> directories;
    std::filesystem::path directory = top / std::filesystem::path(relative).relative_path();
    for (int depth = 0; depth < 64; ++depth) {
        directories.push_back(directory);
        if (directory.lexically_normal() == top.lexically_normal() ||
            !directory.has_relative_path())
            break;
        directory = directory.parent_path();
    }
    return directories;
}

std::optional<double> tightest(std::optional<double> a, std::optional<double> b) {
    if (!a) return b;
    if (!b) return a;
    return std::min(*a, *b);
}

}  // namespace

std::optional<double> parse_cpu_max(std::string_view text) {
    const auto fields = split(trim(text), ' ');
    if (fields.size() != 2 || fields[0] == "max") return std::nullopt;
    return ratio(to_number(fields[0]), to_number(fields[1]));
}

std::optional<double> parse_cfs_quota(std::string_view quota, std::string_view period) {
    return ratio(to_number(quota), to_number(period));
}

std::optional<double> cgroup_cpu_limit(const std::filesystem::path& proc_self_cgroup,
                                       const std::filesystem::path& mountinfo,
                                       const std::filesystem::path& root) {
    const auto groups = read_text(proc_self_cgroup);
    const auto mounts = read_text(mountinfo);
    if (!groups || !mounts) return std::nullopt;
    std::optional<double> limit;
    const auto v2_mount = find_mount(*mounts, true);
    const auto v2_group = find_group(*groups, true);
    if (v2_mount && v2_group) {
        for (const auto& directory : group_directories(*v2_mount, *v2_group, root)) {
            if (const auto text = read_text(directory / "cpu.max"))
                limit = tightest(limit, parse_cpu_max(*text));
        }
    }
    const auto v1_mount = find_mount(*mounts, false);
    const auto v1_group = find_group(*groups, false);
    if (v1_mount && v1_group) {
        for (const auto& directory : group_directories(*v1_mount, *v1_group, root)) {
            const auto quota = read_text(directory / "cpu.cfs_quota_us");
            const auto period = read_text(directory / "cpu.cfs_period_us");
            if (quota && period) limit = tightest(limit, parse_cfs_quota(*quota, *period));
        }
    }
    return limit;
}

std::optional<int> affinity_cpu_count() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) != 0) return std::nullopt;
    return CPU_COUNT(&set);
}

CpuBudget cpu_budget(const std::filesystem::path& proc_self_cgroup,
                     const std::filesystem::path& mountinfo, const std::filesystem::path& root) {
    CpuBudget budget;
    budget.cgroup_limit = cgroup_cpu_limit(proc_self_cgroup, mountinfo, root);
    budget.affinity = affinity_cpu_count();
    budget.hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    int effective = budget.hardware;
    // A fractional quota (1.5 CPUs) still lets 2 threads make progress, throttled.
    if (budget.cgroup_limit)
        effective = std::min(effective, static_cast<int>(std::ceil(*budget.cgroup_limit)));
    if (budget.affinity) effective = std::min(effective, *budget.affinity);
    budget.effective = std::max(1, effective);
    return budget;
}

std::string describe(const CpuBudget& budget) {
    std::ostringstream text;
    text << "cpus=" << budget.effective << " cpu_quota=";
    if (budget.cgroup_limit) text << *budget.cgroup_limit;
    else text << "none";
    text << " cpu_affinity=";
    if (budget.affinity) text << *budget.affinity;
    else text << "unknown";
    text << " cpu_hardware=" << budget.hardware;
    return text.str();
}

}  // namespace rollgap::service
