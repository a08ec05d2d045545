#include "service/http/routes.h"

#include <algorithm>
#include <array>
#include <vector>

#include "service/analyses/table.h"

namespace rollgap::service::http {
namespace {

// The routes before and after the analyses' (one POST route each, from their rows:
// service/analyses/table.cpp).
constexpr std::array scenario_routes{
    // `default` is served from code; PUT and DELETE on it are answered 422 (a reserved name).
    Route{RouteId::scenarios_default, "/v1/scenarios/default", get | put | del, false, "", false},
    Route{RouteId::scenarios, "/v1/scenarios", get, true, "", false},
    Route{RouteId::scenario, "/v1/scenarios/{name}", get | put | patch | del, true, "", false},
    // GET: the stored posterior; POST: fit new observations with it as the prior, store the
    // result as a new version (docs/model.md §11.6).
    Route{RouteId::scenario_calibrate, "/v1/scenarios/{name}/calibrate", get | post, true, "",
          false},
    // Stored mills (tandem documents), the same rules; `default` is the default mill.
    Route{RouteId::mills_default, "/v1/mills/default", get | put | del, false, "", false},
    Route{RouteId::mills, "/v1/mills", get, true, "", false},
    Route{RouteId::mill, "/v1/mills/{name}", get | put | patch | del, true, "", false},
};
constexpr std::array other_routes{
    Route{RouteId::jobs, "/v1/jobs", get | post, true, "", false},
    Route{RouteId::job, "/v1/jobs/{id}", get | del, true, "", false},
    Route{RouteId::job_events, "/v1/jobs/{id}/events", get, true, "", false},
    Route{RouteId::openapi, "/openapi.json", get, false, "", false},
    Route{RouteId::livez, "/livez", get, false, "", true},
    Route{RouteId::readyz, "/readyz", get, false, "", true},
    Route{RouteId::metrics, "/metrics", get, false, "", true},
    // The browser workbench: the page at / and its files under /static/
    // (service/http/static_files.h).
    Route{RouteId::page, "/", get, false, "", false},
    Route{RouteId::static_file, "/static/{file}", get, false, "", false},
};

const std::vector<Route>& route_table() {
    static const std::vector<Route> routes = [] {
        std::vector<Route> all(scenario_routes.begin(), scenario_routes.end());
        for (const Analysis& analysis : analyses())
            all.push_back({RouteId::analysis, analysis.path, post, true, analysis.name, false});
        all.insert(all.end(), other_routes.begin(), other_routes.end());
        return all;
    }();
    return routes;
}

}  // namespace

constexpr std::string_view static_prefix = "/static/";

std::span<const Route> all_routes() { return route_table(); }

const Route* match_route(std::string_view path) {
    for (const Route& route : route_table()) {
        if (route.id == RouteId::static_file) {
            if (path.starts_with(static_prefix)) return &route;
        } else if (route.id == RouteId::scenario_calibrate) {
            if (path.starts_with(scenario_prefix) && path.ends_with(calibrate_suffix) &&
                path.size() > scenario_prefix.size() + calibrate_suffix.size()) {
                const std::string_view name =
                    path.substr(scenario_prefix.size(),
                                path.size() - scenario_prefix.size() - calibrate_suffix.size());
                if (name.find('/') == std::string_view::npos) return &route;
            }
        } else if (route.id == RouteId::job_events) {
            if (path.starts_with(jobs_prefix) && path.ends_with(events_suffix) &&
                path.size() > jobs_prefix.size() + events_suffix.size()) {
                const std::string_view id = path.substr(
                    jobs_prefix.size(), path.size() - jobs_prefix.size() - events_suffix.size());
                if (id.find('/') == std::string_view::npos) return &route;
            }
        } else if (route.id == RouteId::job || route.id == RouteId::scenario ||
                   route.id == RouteId::mill) {
            const std::string_view prefix = route.id == RouteId::job        ? jobs_prefix
                                            : route.id == RouteId::scenario ? scenario_prefix
                                                                            : mill_prefix;
            if (path.size() > prefix.size() && path.starts_with(prefix) &&
                path.find('/', prefix.size()) == std::string_view::npos) {
                return &route;
            }
        } else if (path == route.pattern) {
            return &route;
        }
    }
    return nullptr;
}

std::string allow_header(const Route& route) {
    std::string allow;
    const auto add = [&allow](std::string_view method) {
        if (!allow.empty()) allow += ", ";
        allow += method;
    };
    if (route.methods & get) {
        add("GET");
        add("HEAD");
    }
    if (route.methods & post) add("POST");
    if (route.methods & put) add("PUT");
    if (route.methods & patch) add("PATCH");
    if (route.methods & del) add("DELETE");
    add("OPTIONS");
    return allow;
}

bool method_allowed(const Route& route, std::string_view method) {
    if (method == "GET" || method == "HEAD") return (route.methods & get) != 0;
    if (method == "POST") return (route.methods & post) != 0;
    if (method == "PUT") return (route.methods & put) != 0;
    if (method == "PATCH") return (route.methods & patch) != 0;
    if (method == "DELETE") return (route.methods & del) != 0;
    return false;
}

bool answers_csv(const Route& route, std::string_view method) {
    if (route.id == RouteId::job) return method == "GET" || method == "HEAD";
    if (route.id != RouteId::analysis || method != "POST") return false;
    const Analysis* analysis = find_analysis(analyses(), route.analysis);
    // A batch's route answers with the job it queued; its rows are CSV from GET /v1/jobs/{id}.
    return analysis != nullptr && analysis->subject() != Subject::batch &&
           !analysis->tables().empty();
}

std::vector<std::string_view> route_media_types(const Route& route, std::string_view method) {
    switch (route.id) {
        case RouteId::static_file: return {};
        case RouteId::page: return {"text/html"};
        case RouteId::metrics: return {"text/plain"};
        case RouteId::job_events: return {"text/event-stream"};
        default:
            if (answers_csv(route, method)) return {"application/json", "text/csv"};
            return {"application/json"};
    }
}

std::string_view method_label(std::string_view method) {
    static constexpr std::array<std::string_view, 9> known{
        "GET", "HEAD", "POST", "PUT", "DELETE", "OPTIONS", "PATCH", "CONNECT", "TRACE"};
    const auto found = std::find(known.begin(), known.end(), method);
    return found == known.end() ? std::string_view("other") : *found;
}

}  // namespace rollgap::service::http
