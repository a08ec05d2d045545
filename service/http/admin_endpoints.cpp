#include "service/http/admin_endpoints.h"

#include <fstream>
#include <optional>
#include <vector>

#include <unistd.h>

#include "api/text.h"
#include "service/http/responses.h"
#include "service/version.h"

namespace rollgap::service::http {
namespace {

std::optional<double> resident_memory_bytes() {
    std::ifstream statm("/proc/self/statm");
    long pages_total = 0, pages_resident = 0;
    if (!(statm >> pages_total >> pages_resident)) return std::nullopt;
    return static_cast<double>(pages_resident) * static_cast<double>(sysconf(_SC_PAGESIZE));
}

}  // namespace

void answer_admin(RouteId route, ServiceState& state, httplib::Response& response) {
    const ServerConfig& config = state.config;
    switch (route) {
        case RouteId::livez:
            set_json(response, 200,
                     {{"status", "alive"}, {"instance", config.instance}, {"version", version()}},
                     "application/json");
            return;
        case RouteId::readyz:
            if (state.draining) {
                state.overloaded(response, "the service is shutting down");
            } else {
                // A store outage leaves the service ready (synchronous analyses never need the
                // store); the body says it, from the probe's last answer (never a store call).
                const auto store = state.store.snapshot();
                nlohmann::json store_state = {{"up", store.up}};
                if (!store.up) store_state["detail"] = store.reason;
                set_json(response, 200,
                         {{"status", "ready"},
                          {"instance", config.instance},
                          {"version", version()},
                          {"store", std::move(store_state)}},
                         "application/json");
            }
            return;
        case RouteId::metrics:
            response.status = 200;
            response.set_content(metrics_text(state), "text/plain; version=0.0.4; charset=utf-8");
            return;
        default:
            set_problem(response, api::ProblemCode::internal, "no admin handler for this route");
            return;
    }
}

std::string metrics_text(ServiceState& state) {
    const WorkerPoolStats stats = state.pool.stats();
    // Jobs by state (shared by all replicas) and the store's state are the background probe's
    // last answer: a scrape never waits on the store. The counts stay at their last known
    // values while it is down; absent until it answered once.
    const StoreHandle::Snapshot probed = state.store.snapshot();
    const std::optional<store::JobCounts>& counts = probed.counts;
    std::vector<GaugeSample> gauges{
        {"rollgap_workers", "Compute worker threads.", "", static_cast<double>(stats.workers)},
        {"rollgap_workers_busy", "Compute workers running an analysis.", "",
         static_cast<double>(stats.busy)},
        {"rollgap_queue_depth",
         "Work waiting for a worker, by lane (interactive: synchronous requests, "
         "batch: jobs).",
         "lane=\"interactive\"", static_cast<double>(stats.interactive_queued)},
        {"rollgap_queue_depth", "", "lane=\"batch\"", static_cast<double>(stats.batch_queued)},
        {"rollgap_queue_capacity", "Work that may wait for a worker, by lane.",
         "lane=\"interactive\"", static_cast<double>(stats.interactive_capacity)},
        {"rollgap_queue_capacity", "", "lane=\"batch\"", static_cast<double>(stats.batch_capacity)},
        {"rollgap_requests_in_flight", "Synchronous compute requests read and not yet answered.",
         "", static_cast<double>(state.in_flight.load())},
        {"rollgap_jobs_capacity", "Jobs the store holds at most.", "",
         static_cast<double>(state.config.max_jobs)},
        {"rollgap_ready", "1 while the service accepts work, 0 while it drains.", "",
         state.draining ? 0.0 : 1.0},
        {"rollgap_store_up",
         "1 while the job store accepts writes (a probe every second, and every operation), 0 "
         "while it is unavailable (jobs and stored scenarios answer 503; synchronous analyses "
         "are unaffected).",
         "", probed.up ? 1.0 : 0.0},
        {"process_start_time_seconds", "Start time of the process since the Unix epoch, seconds.",
         "", std::chrono::duration<double>(state.start_time.time_since_epoch()).count()},
    };
    if (counts) {
        const std::size_t by_state[] = {counts->queued, counts->running, counts->succeeded,
                                        counts->failed, counts->cancelled};
        for (std::size_t i = 0; i < std::size(by_state); ++i) {
            const auto state_name = store::job_state_name(static_cast<store::JobState>(i));
            gauges.push_back(
                {"rollgap_jobs", i == 0 ? "Jobs in the store (all replicas) by state." : "",
                 api::concat("state=\"", state_name, "\""), static_cast<double>(by_state[i])});
        }
    }
    if (const auto rss = resident_memory_bytes()) {
        gauges.push_back(
            {"process_resident_memory_bytes", "Resident memory size, bytes.", "", *rss});
    }
    // HELP lines come from the first sample of each name.
    std::string previous_help;
    for (GaugeSample& gauge : gauges) {
        if (gauge.help.empty()) {
            gauge.help = previous_help;
        } else {
            previous_help = gauge.help;
        }
    }
    return state.metrics.render(gauges);
}

}  // namespace rollgap::service::http
