#pragma once
// Prometheus metrics of the HTTP service, rendered in the text exposition format 0.0.4.
//
// Counters and histograms are recorded as requests and computations finish; gauges (queue
// depth, busy workers, jobs) are read from their owners at scrape time and passed to render().
// Every label value comes from a closed set (routes of the route table, known analyses, HTTP
// status codes, methods httplib parses), so no client input can grow the label space.

#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

namespace rollgap::service {

inline constexpr std::array<double, 15> request_duration_buckets{
    0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30};
inline constexpr std::array<double, 15> analysis_duration_buckets{
    0.0005, 0.001, 0.0025, 0.005, 0.01, 0.05, 0.1, 0.5, 1, 5, 10, 30, 60, 300, 600};

class Histogram {
public:
    explicit Histogram(std::span<const double> upper_bounds);
    void observe(double value);
    std::span<const double> upper_bounds() const { return bounds_; }
    const std::vector<std::uint64_t>& bucket_counts() const { return counts_; }  // not cumulative
    std::uint64_t count() const { return count_; }
    double sum() const { return sum_; }

private:
    std::span<const double> bounds_;
    std::vector<std::uint64_t> counts_;  // one per bound, plus +Inf
    std::uint64_t count_ = 0;
    double sum_ = 0.0;
};

struct GaugeSample {
    std::string name;  // rollgap_queue_depth
    std::string help;
    std::string labels;  // rendered: lane="interactive" (empty: none)
    double value = 0.0;
};

class Metrics {
public:
    // One finished HTTP request. `route` is a route-table pattern or "unmatched".
    void observe_request(std::string_view method, std::string_view route, int status,
                         double seconds);

    // One computation that ran on a worker; `outcome`: succeeded, rejected (4xx problem),
    // deadline_exceeded, cancelled, failed (5xx problem).
    void observe_analysis(std::string_view analysis, std::string_view outcome, double seconds);

    // A solver that did not converge (result status solver_failure) or an internal error.
    void count_solver_failure(std::string_view analysis, std::string_view reason);

    // Work dropped before it ran: deadline passed or cancelled while queued.
    void count_skipped(std::string_view reason);

    // A job's work item this replica claimed and finished; `outcome`: succeeded, failed,
    // cancelled, released (given back to the store), lost (lease lost, result discarded),
    // unstored (the store did not take the result).
    void count_work_item(std::string_view outcome);

    // An attempt at a completion callback; `outcome`: delivered, retried, failed (given up).
    void count_webhook_delivery(std::string_view outcome);

    // Everything, plus `gauges`, plus rollgap_build_info.
    std::string render(std::span<const GaugeSample> gauges) const;

    // The count of requests recorded with these labels (tests).
    std::uint64_t request_count(std::string_view method, std::string_view route, int status) const;

private:
    using RequestKey = std::tuple<std::string, std::string, int>;  // method, route, status
    using AnalysisKey = std::tuple<std::string, std::string>;      // analysis, outcome

    mutable std::mutex mutex_;
    std::map<RequestKey, Histogram> requests_;
    std::map<AnalysisKey, Histogram> analyses_;
    std::map<AnalysisKey, std::uint64_t> solver_failures_;  // analysis, reason
    std::map<std::string, std::uint64_t> skipped_;
    std::map<std::string, std::uint64_t> work_items_;
    std::map<std::string, std::uint64_t> webhook_deliveries_;
};

// Escapes a label value (backslash, double quote, newline).
std::string escape_label_value(std::string_view value);

}  // namespace rollgap::service
