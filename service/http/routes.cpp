#include "service/http/routes.h"

#include <algorithm>
#include <array>

namespace rollgap::service::http {
namespace {

constexpr std::array routes{
    // `default` is served from code; PUT and DELETE on it are answered 422 (a reserved name).
    Route{RouteId::scenarios_default, "/v1/scenarios/default", get | put | del, false, "", false},
    Route{RouteId::scenarios, "/v1/scenarios", get, true, "", false},
    Route{RouteId::scenario, "/v1/scenarios/{name}", get | put | del, true, "", false},
    Route{RouteId::roll_gap, "/v1/roll-gap", post, true, "roll_gap", false},
    Route{RouteId::stability, "/v1/stability", post, true, "stability", false},
    Route{RouteId::amplitude, "/v1/amplitude", post, true, "amplitude", false},
    Route{RouteId::tension_cycle, "/v1/tension-cycle", post, true, "tension_cycle", false},
    Route{RouteId::sweeps, "/v1/sweeps", post, true, "sweep", false},
    Route{RouteId::maps, "/v1/maps", post, true, "map", false},
    Route{RouteId::evaluate, "/v1/evaluate", post, true, "evaluate", false},
    Route{RouteId::calibrate, "/v1/calibrate", post, true, "calibrate", false},
    Route{RouteId::jobs, "/v1/jobs", get | post, true, "", false},
    Route{RouteId::job, "/v1/jobs/{id}", get | del, true, "", false},
    Route{RouteId::openapi, "/openapi.json", get, false, "", false},
    Route{RouteId::livez, "/livez", get, false, "", true},
    Route{RouteId::readyz, "/readyz", get, false, "", true},
    Route{RouteId::metrics, "/metrics", get, false, "", true},
    // The browser workbench: the page at / and its files under /static/
    // (service/http/static_files.h).
    Route{RouteId::page, "/", get, false, "", false},
    Route{RouteId::static_file, "/static/{file}", get, false, "", false},
};

}  // namespace

constexpr std::string_view static_prefix = "/static/";

std::span<const Route> all_routes() { return routes; }

const Route* match_route(std::string_view path) {
    for (const Route& route : routes) {
        if (route.id == RouteId::static_file) {
            if (path.starts_with(static_prefix)) return &route;
        } else if (route.id == RouteId::job || route.id == RouteId::scenario) {
            const std::string_view prefix =
                route.id == RouteId::job ? jobs_prefix : scenario_prefix;
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
    if (route.methods & del) add("DELETE");
    add("OPTIONS");
    return allow;
}

bool method_allowed(const Route& route, std::string_view method) {
    if (method == "GET" || method == "HEAD") return (route.methods & get) != 0;
    if (method == "POST") return (route.methods & post) != 0;
    if (method == "PUT") return (route.methods & put) != 0;
    if (method == "DELETE") return (route.methods & del) != 0;
    return false;
}

std::string_view method_label(std::string_view method) {
    static constexpr std::array<std::string_view, 9> known{
        "GET", "HEAD", "POST", "PUT", "DELETE", "OPTIONS", "PATCH", "CONNECT", "TRACE"};
    const auto found = std::find(known.begin(), known.end(), method);
    return found == known.end() ? std::string_view("other") : *found;
}

}  // namespace rollgap::service::http
