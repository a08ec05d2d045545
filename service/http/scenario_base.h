#pragma once
// A request's "base": "<name>": the scenario patch merges onto that stored scenario instead of
// the default. Resolved by the HTTP layer (it has the store) before the facade validates the
// request, for synchronous analyses and at job submission alike, so that a job's stored request
// is self-contained and a re-run on any replica computes the same thing.

#include <optional>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "service/evaluate.h"
#include "service/http/service_state.h"

namespace rollgap::service::http {

// A request without "base" (absent or null) is left as it is and the store is not touched.
// Otherwise the stored scenario is fetched and the request rewritten to
//     {"base": {"name", "version"}, "scenario": merge_patch(stored, patch), ...}
// which the facade computes and echoes (the result's "base"). Returns the problem instead:
// 422 at /base (not a name, or no such stored scenario), 503 store_unavailable.
std::optional<Outcome> resolve_base(nlohmann::json& request, ServiceState& state);

// A stored posterior (its text; "" for none) still describes a scenario edited from `before` to
// `after` only while every field it describes keeps its value: the posterior, else "". Used
// wherever a stored stand is edited or patched (a new version, a request's base, a mill's stand).
std::string posterior_still_centred(const std::string& posterior, const nlohmann::json& before,
                                    const nlohmann::json& after);

// Answers what resolve_base() refused: a store_unavailable problem gets Retry-After.
void answer_unresolved(ServiceState& state, const Outcome& refused, httplib::Response& response);

}  // namespace rollgap::service::http
