#include "service/http/scenario_base.h"

#include "api/json_text.h"
#include "api/request_json.h"
#include "api/text.h"
#include "service/http/responses.h"

namespace rollgap::service::http {

using api::concat;
using nlohmann::json;

namespace {

Outcome base_problem(std::string detail, std::string error) {
    return problem_outcome(
        api::make_problem(api::ProblemCode::invalid_request, std::move(detail),
                          {{"/base", std::move(error),
                            std::string(api::stored_scenario_name_pattern), std::nullopt}}));
}

}  // namespace

std::optional<Outcome> resolve_base(json& request, ServiceState& state) {
    if (!request.is_object()) return std::nullopt;  // the facade reports it
    const auto found = request.find("base");
    if (found == request.end() || found->is_null()) return std::nullopt;
    // A client names a stored scenario; the resolved {"name", "version"} form is what this
    // function writes, never something a client may claim.
    if (!found->is_string()) {
        return base_problem("\"base\" must name a stored scenario",
                            concat("must be a string, not ", api::json_type_name(*found)));
    }
    const std::string name = found->get<std::string>();
    if (auto error = api::stored_scenario_name_error(name, "/base")) {
        return problem_outcome(api::make_problem(api::ProblemCode::invalid_request,
                                                 "\"base\" is not a stored scenario's name",
                                                 {std::move(*error)}));
    }

    const auto store = state.store.get();
    if (!store) {
        state.store.report(store::StoreStatus::unavailable);
        return problem_outcome(
            api::make_problem(api::ProblemCode::store_unavailable,
                              "the scenario store is unavailable, so \"base\" cannot be "
                              "resolved; retry later, or send the scenario itself"));
    }
    auto stored = store->get_scenario(name);
    state.store.report(stored.status);
    if (stored.status == store::StoreStatus::not_found) {
        return base_problem(concat("no stored scenario ", api::quoted_for_message(name)),
                            "names no stored scenario; GET /v1/scenarios lists them");
    }
    if (!stored.ok()) {
        return problem_outcome(
            api::make_problem(api::ProblemCode::store_unavailable,
                              "the scenario store did not answer, so \"base\" cannot be "
                              "resolved; retry later, or send the scenario itself"));
    }
    auto parsed = api::parse_json_text(stored.value->body);
    if (std::holds_alternative<api::Problem>(parsed)) {
        // Only this service writes the table, always valid JSON: a corrupted row is a fault.
        return problem_outcome(api::make_problem(api::ProblemCode::internal,
                                                 concat("stored scenario ", name, " is not JSON")));
    }
    json scenario = std::move(std::get<json>(parsed));
    // null and absent are the same patch: nothing changes.
    if (const auto patch = request.find("scenario"); patch != request.end() && !patch->is_null())
        scenario.merge_patch(*patch);
    request["scenario"] = std::move(scenario);
    request["base"] = api::scenario_base_json({name, stored.value->version});
    return std::nullopt;
}

void answer_unresolved(ServiceState& state, const Outcome& refused, httplib::Response& response) {
    if (refused.problem == api::ProblemCode::store_unavailable) {
        state.store_unavailable(response, refused.body.value("detail", std::string()));
        return;
    }
    set_json(response, refused.http_status, refused.body, refused.media_type());
}

}  // namespace rollgap::service::http
