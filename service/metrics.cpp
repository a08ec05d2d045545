#include "service/metrics.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <sstream>

#include "service/version.h"

namespace rollgap::service {
namespace {

std::string number_text(double value) {
    if (std::isnan(value)) return "NaN";
    if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
    std::array<char, 64> text{};
    // Shortest round trip, %g style: 0.0005 rather than 5e-04.
    const auto written =
        std::to_chars(text.data(), text.data() + text.size(), value, std::chars_format::general);
    return std::string(text.data(), written.ptr);
}

std::string label(std::string_view name, std::string_view value) {
    std::string text(name);
    text += "=\"";
    text += escape_label_value(value);
    text += '"';
    return text;
}

std::string join_labels(std::string_view a, std::string_view b) {
    if (a.empty()) return std::string(b);
    if (b.empty()) return std::string(a);
    std::string text(a);
    text += ',';
    text += b;
    return text;
}

void write_histogram(std::ostream& out, std::string_view name, const std::string& labels,
                     const Histogram& histogram) {
    std::uint64_t cumulative = 0;
    const auto bounds = histogram.upper_bounds();
    const auto& counts = histogram.bucket_counts();
    for (std::size_t i = 0; i <= bounds.size(); ++i) {
        cumulative += counts[i];
        const std::string le = i < bounds.size() ? number_text(bounds[i]) : std::string("+Inf");
        out << name << "_bucket{" << join_labels(labels, label("le", le)) << "} " << cumulative
            << '\n';
    }
    const std::string braces = labels.empty() ? std::string() : "{" + labels + "}";
    out << name << "_sum" << braces << ' ' << number_text(histogram.sum()) << '\n';
    out << name << "_count" << braces << ' ' << histogram.count() << '\n';
}

std::string compiler_text() {
#if defined(__clang__)
    return "clang " __clang_version__;
#elif defined(__GNUC__)
    return "gcc " __VERSION__;
#else
    return "unknown";
#endif
}

}  // namespace

Histogram::Histogram(std::span<const double> upper_bounds)
    : bounds_(upper_bounds), counts_(upper_bounds.size() + 1, 0) {}

void Histogram::observe(double value) {
    if (!std::isfinite(value)) return;
    const auto bucket =
        std::lower_bound(bounds_.begin(), bounds_.end(), value);  // le: value <= bound
    ++counts_[static_cast<std::size_t>(bucket - bounds_.begin())];
    ++count_;
    sum_ += value;
}

std::string escape_label_value(std::string_view value) {
    std::string text;
    text.reserve(value.size());
    for (const char c : value) {
        if (c == '\\') {
            text += "\\\\";
        } else if (c == '"') {
            text += "\\\"";
        } else if (c == '\n') {
            text += "\\n";
        } else {
            text += c;
        }
    }
    return text;
}

void Metrics::observe_request(std::string_view method, std::string_view route, int status,
                              double seconds) {
    std::lock_guard lock(mutex_);
    auto [entry, inserted] = requests_.try_emplace(
        RequestKey{std::string(method), std::string(route), status}, request_duration_buckets);
    entry->second.observe(seconds);
}

void Metrics::observe_analysis(std::string_view analysis, std::string_view outcome,
                               double seconds) {
    std::lock_guard lock(mutex_);
    auto [entry, inserted] = analyses_.try_emplace(
        AnalysisKey{std::string(analysis), std::string(outcome)}, analysis_duration_buckets);
    entry->second.observe(seconds);
}

void Metrics::count_solver_failure(std::string_view analysis, std::string_view reason) {
    std::lock_guard lock(mutex_);
    ++solver_failures_[AnalysisKey{std::string(analysis), std::string(reason)}];
}

void Metrics::count_skipped(std::string_view reason) {
    std::lock_guard lock(mutex_);
    ++skipped_[std::string(reason)];
}

void Metrics::count_work_item(std::string_view outcome) {
    std::lock_guard lock(mutex_);
    ++work_items_[std::string(outcome)];
}

void Metrics::count_webhook_delivery(std::string_view outcome) {
    std::lock_guard lock(mutex_);
    ++webhook_deliveries_[std::string(outcome)];
}

std::uint64_t Metrics::request_count(std::string_view method, std::string_view route,
                                     int status) const {
    std::lock_guard lock(mutex_);
    const auto found = requests_.find(RequestKey{std::string(method), std::string(route), status});
    return found == requests_.end() ? 0 : found->second.count();
}

std::string Metrics::render(std::span<const GaugeSample> gauges) const {
    std::ostringstream out;
    {
        std::lock_guard lock(mutex_);

        out << "# HELP rollgap_http_requests_total HTTP requests answered, by method, route and status.\n"
               "# TYPE rollgap_http_requests_total counter\n";
        for (const auto& [key, histogram] : requests_) {
            const auto& [method, route, status] = key;
            out << "rollgap_http_requests_total{" << label("method", method) << ','
                << label("route", route) << ',' << label("status", std::to_string(status)) << "} "
                << histogram.count() << '\n';
        }

        out << "# HELP rollgap_http_request_duration_seconds Time from routing to the response, by method, "
               "route and status.\n"
               "# TYPE rollgap_http_request_duration_seconds histogram\n";
        for (const auto& [key, histogram] : requests_) {
            const auto& [method, route, status] = key;
            write_histogram(out, "rollgap_http_request_duration_seconds",
                            join_labels(join_labels(label("method", method), label("route", route)),
                                        label("status", std::to_string(status))),
                            histogram);
        }

        out << "# HELP rollgap_analysis_duration_seconds Time an analysis ran on a worker, by analysis and "
               "outcome.\n"
               "# TYPE rollgap_analysis_duration_seconds histogram\n";
        for (const auto& [key, histogram] : analyses_) {
            const auto& [analysis, outcome] = key;
            write_histogram(out, "rollgap_analysis_duration_seconds",
                            join_labels(label("analysis", analysis), label("outcome", outcome)),
                            histogram);
        }

        out << "# HELP rollgap_solver_failures_total Analyses whose solver failed or that raised an internal "
               "error, by analysis and reason.\n"
               "# TYPE rollgap_solver_failures_total counter\n";
        for (const auto& [key, count] : solver_failures_) {
            const auto& [analysis, reason] = key;
            out << "rollgap_solver_failures_total{" << label("analysis", analysis) << ','
                << label("reason", reason) << "} " << count << '\n';
        }

        out << "# HELP rollgap_work_skipped_total Queued work dropped before it ran, by reason.\n"
               "# TYPE rollgap_work_skipped_total counter\n";
        for (const auto& [reason, count] : skipped_) {
            out << "rollgap_work_skipped_total{" << label("reason", reason) << "} " << count
                << '\n';
        }

        out << "# HELP rollgap_work_items_total Job work items this replica claimed and finished, "
               "by outcome.\n"
               "# TYPE rollgap_work_items_total counter\n";
        for (const auto& [outcome, count] : work_items_) {
            out << "rollgap_work_items_total{" << label("outcome", outcome) << "} " << count
                << '\n';
        }

        out << "# HELP rollgap_webhook_deliveries_total Attempts at completion callbacks this "
               "replica made, by outcome (delivered, retried, failed: given up).\n"
               "# TYPE rollgap_webhook_deliveries_total counter\n";
        for (const auto& [outcome, count] : webhook_deliveries_) {
            out << "rollgap_webhook_deliveries_total{" << label("outcome", outcome) << "} " << count
                << '\n';
        }
    }

    // Gauges: grouped by name, HELP and TYPE once per name.
    std::vector<const GaugeSample*> sorted;
    for (const GaugeSample& gauge : gauges) sorted.push_back(&gauge);
    std::stable_sort(sorted.begin(), sorted.end(),
                     [](const GaugeSample* a, const GaugeSample* b) { return a->name < b->name; });
    std::string_view previous;
    for (const GaugeSample* gauge : sorted) {
        if (gauge->name != previous) {
            out << "# HELP " << gauge->name << ' ' << gauge->help << '\n'
                << "# TYPE " << gauge->name << " gauge\n";
            previous = gauge->name;
        }
        out << gauge->name;
        if (!gauge->labels.empty()) out << '{' << gauge->labels << '}';
        out << ' ' << number_text(gauge->value) << '\n';
    }

    out << "# HELP rollgap_build_info The running build; the value is always 1.\n"
           "# TYPE rollgap_build_info gauge\n"
        << "rollgap_build_info{" << label("version", version()) << ','
        << label("compiler", compiler_text()) << "} 1\n";
    return out.str();
}

}  // namespace rollgap::service
