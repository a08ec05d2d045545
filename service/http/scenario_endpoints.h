#pragma once
// Stored stand scenarios: PUT/GET/DELETE /v1/scenarios/{name} and GET /v1/scenarios, kept in
// the job store by name and versioned (ETag "<version>", If-Match / If-None-Match), so that two
// editors cannot overwrite each other. A name's versions count up across delete and re-create
// (a stale ETag never matches a new scenario); each records its author and time. A body is a merge
// patch onto the default scenario, validated as an analysis' scenario is; the resolved full
// scenario is stored. `default` is the built-in default, served from code (GET
// /v1/scenarios/default) and never stored.
//
// Stored mills (docs/http-api.md): PUT/GET/DELETE /v1/mills/{name} and GET /v1/mills, the same
// rules over the same versions with kind `mill`: a body is a merge patch onto the default
// tandem document, the resolved document is stored, and a tandem request names it in "base".
// A name is a stand or a mill at a time (one version counter per name).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "service/http/routes.h"
#include "service/http/service_state.h"
#include "service/http/sync_dispatch.h"

namespace rollgap::service::http {

struct EntityTags;

class ScenarioEndpoints {
public:
    // The stand scenarios (kind stand, /v1/scenarios/) or the mills (kind mill, /v1/mills/).
    ScenarioEndpoints(ServiceState& state, store::StoredKind kind);

    // Page sizes of GET /v1/scenarios (?limit=&cursor=), as GET /v1/jobs.
    static constexpr std::size_t default_page = 50;
    static constexpr std::size_t max_page = 200;

    // GET /v1/scenarios, GET and DELETE /v1/scenarios/{name}; `default` is the built-in default
    // (GET: served from code, never the store; DELETE → 422). The same under /v1/mills.
    // `client` (the key's name) is recorded as the author of what a write stores.
    void get_or_delete(const httplib::Request& request, const std::string& client,
                       httplib::Response& response);
    // PUT /v1/scenarios/{name}; `body` is the parsed request body ({} when empty).
    void put(const httplib::Request& request, nlohmann::json body, const std::string& client,
             httplib::Response& response);
    // PATCH /v1/scenarios/{name} (application/merge-patch+json): the patch merged onto the
    // stored document (not onto the default, as PUT's body is), validated and stored as a new
    // version over the one it was merged onto (If-Match / If-None-Match as for PUT).
    void patch(const httplib::Request& request, nlohmann::json body, const std::string& client,
               httplib::Response& response);
    // POST /v1/scenarios/{name}/calibrate (docs/model.md §11.6): the body's `options` are a
    // calibration of the stored stand, whose posterior (the part on the fitted fields) is the
    // joint prior unless the options give one; a converged fit is stored as a new version over
    // the one If-Match names (required), the calibrated scenario with its posterior, and the
    // answer is calibrate's with "stored": {name, version}. Computed like a synchronous route.
    void calibrate(const httplib::Request& request, nlohmann::json body, const std::string& client,
                   SteadyClock::time_point arrival, SyncDispatch& sync,
                   httplib::Response& response);

private:
    void list(const httplib::Request& request, httplib::Response& response);
    // ?version=N: that version of the name, one of the last ones kept.
    void get(const std::string& name, const httplib::Request& request, httplib::Response& response);
    void remove(const std::string& name, const httplib::Request& request, const std::string& client,
                httplib::Response& response);
    // GET /v1/scenarios/{name}/calibrate: the current version's stored posterior (null: none).
    void posterior(const std::string& name, httplib::Response& response);

    // The version a write may replace under the request's If-Match / If-None-Match: the one
    // If-Match names (compared by the store inside its transaction), or, for "*", lists and
    // If-None-Match tags, the current one once compared (RFC 9110 §13.2.2). False: refused
    // and answered (412, 503).
    bool expected_version(store::JobStore& store, const std::string& name,
                          const EntityTags& if_match, const EntityTags& if_none_match,
                          std::optional<std::int64_t>& expected, httplib::Response& response);

    // True when `errors` is empty; else the 422 naming every violation in `what` (false).
    bool accepted(const api::FieldErrors& errors, const std::string& what,
                  httplib::Response& response) const;
    // The body's plant units rewritten to canonical keys, or false when refused (422 answered).
    bool canonical_body(nlohmann::json& body, httplib::Response& response) const;
    // The request's body read as this collection's document: the resolved document to store, or
    // false when refused (422 answered).
    bool resolve_body(const nlohmann::json& body, nlohmann::json& resolved,
                      httplib::Response& response) const;
    // The current version of `name` in this collection, or nothing with 404 or 503 answered.
    std::optional<store::StoredScenario> stored(store::JobStore& store, const std::string& name,
                                                httplib::Response& response);
    // 404 naming this collection; a name of the other kind is pointed to its own collection.
    void not_found(const std::string& name, httplib::Response& response) const;
    bool refuse_name(const std::string& name, httplib::Response& response) const;
    void precondition_failed(httplib::Response& response, const std::string& name) const;

    ServiceState& state_;
    store::StoredKind kind_;
    std::string_view prefix_;   // "/v1/scenarios/" or "/v1/mills/"
    std::string_view noun_;     // "scenario" or "mill"
    std::string default_text_;  // the built-in default document (GET .../default)
};

}  // namespace rollgap::service::http
