#pragma once
// The route table of the HTTP service: every path, the methods it takes, whether it needs the
// bearer token, which analysis it runs, and whether the admin listener serves it too.

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rollgap::service::http {

enum Method : unsigned { get = 1, post = 2, del = 4, put = 8, patch = 16 };

enum class RouteId {
    scenarios_default,
    scenarios,
    scenario,
    scenario_calibrate,  // a stored stand calibrated from new observations (its posterior kept)
    mills_default,
    mills,
    mill,
    analysis,  // the synchronous route of an analysis (Route::analysis names it)
    jobs,
    job,
    job_events,  // GET: the job's progress as server-sent events
    openapi,
    livez,
    readyz,
    metrics,
    page,
    static_file,
};

struct Route {
    RouteId id;
    std::string_view pattern;  // also the metrics label
    unsigned methods;
    bool compute;               // needs the bearer token when one is configured
    std::string_view analysis;  // the facade's analysis for the synchronous compute routes
    bool admin;                 // served by the admin listener as well
};

inline constexpr std::string_view unmatched_route = "unmatched";
inline constexpr std::string_view jobs_prefix = "/v1/jobs/";
inline constexpr std::string_view scenario_prefix = "/v1/scenarios/";
inline constexpr std::string_view mill_prefix = "/v1/mills/";
inline constexpr std::string_view calibrate_suffix = "/calibrate";
inline constexpr std::string_view events_suffix = "/events";

std::span<const Route> all_routes();

// The route of `path`, or nullptr.
const Route* match_route(std::string_view path);

// "GET, HEAD, POST, OPTIONS": the Allow header of `route`.
std::string allow_header(const Route& route);
bool method_allowed(const Route& route, std::string_view method);
// The media types `method` on `route` answers with besides problem details (which every route
// may send): application/json, text/csv where a result has tables, text/plain for the
// metrics, text/html for the page; empty for the workbench's files (each its own type).
std::vector<std::string_view> route_media_types(const Route& route, std::string_view method);
// Whether the answer depends on the Accept header (JSON or CSV): Vary: Accept.
bool answers_csv(const Route& route, std::string_view method);

// A closed set for the metrics label.
std::string_view method_label(std::string_view method);

}  // namespace rollgap::service::http
