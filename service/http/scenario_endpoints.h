#pragma once
// Stored stand scenarios: PUT/GET/DELETE /v1/scenarios/{name} and GET /v1/scenarios, kept in
// the job store by name and versioned (ETag "<version>", If-Match / If-None-Match), so that two
// editors cannot overwrite each other. A name's versions count up across delete and re-create
// (a stale ETag never matches a new scenario); each records its author and time. A body is a merge
// patch onto the default scenario, validated as an analysis' scenario is; the resolved full
// scenario is stored. `default` is the built-in default, served from code (GET
// /v1/scenarios/default) and never stored.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "service/http/routes.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

struct EntityTags;

class ScenarioEndpoints {
public:
    explicit ScenarioEndpoints(ServiceState& state) : state_(state) {}

    // Page sizes of GET /v1/scenarios (?limit=&cursor=), as GET /v1/jobs.
    static constexpr std::size_t default_page = 50;
    static constexpr std::size_t max_page = 200;

    // GET /v1/scenarios, GET and DELETE /v1/scenarios/{name} (also `default`: DELETE → 422).
    // `client` (the key's name) is recorded as the author of what a write stores.
    void get_or_delete(const httplib::Request& request, const std::string& client,
                       httplib::Response& response);
    // PUT /v1/scenarios/{name}; `body` is the parsed request body ({} when empty).
    void put(const httplib::Request& request, nlohmann::json body, const std::string& client,
             httplib::Response& response);

private:
    void list(const httplib::Request& request, httplib::Response& response);
    void get(const std::string& name, httplib::Response& response);
    void remove(const std::string& name, const httplib::Request& request, const std::string& client,
                httplib::Response& response);

    // The version a write may replace under the request's If-Match / If-None-Match: the one
    // If-Match names (compared by the store inside its transaction), or, for "*", lists and
    // If-None-Match tags, the current one once compared (RFC 9110 §13.2.2). False: refused
    // and answered (412, 503).
    bool expected_version(store::JobStore& store, const std::string& name,
                          const EntityTags& if_match, const EntityTags& if_none_match,
                          std::optional<std::int64_t>& expected, httplib::Response& response);

    ServiceState& state_;
};

}  // namespace rollgap::service::http
