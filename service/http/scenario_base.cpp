#include "service/http/scenario_base.h"

#include "api/json_text.h"
#include "api/request_json.h"
#include "api/text.h"
#include "service/analyses/table.h"
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
    // A stand's analysis takes a stored scenario and merges "scenario" onto it; a mill's takes
    // a stored mill and merges "tandem". An unknown analysis is the facade's to report.
    const auto analysis_name = request.find("analysis");
    const Analysis* analysis =
        analysis_name != request.end() && analysis_name->is_string()
            ? find_analysis(analyses(), analysis_name->get_ref<const std::string&>())
            : nullptr;
    const bool mill = analysis != nullptr && analysis->subject() == Subject::mill;
    const store::StoredKind kind = mill ? store::StoredKind::mill : store::StoredKind::stand;
    const std::string_view member = mill ? "tandem" : "scenario";
    const std::string_view noun = mill ? "mill" : "scenario";
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
        return base_problem(concat("no stored ", noun, " ", api::quoted_for_message(name)),
                            concat("names no stored ", noun, "; GET ",
                                   mill ? "/v1/mills" : "/v1/scenarios", " lists them"));
    }
    if (!stored.ok()) {
        return problem_outcome(
            api::make_problem(api::ProblemCode::store_unavailable,
                              "the scenario store did not answer, so \"base\" cannot be "
                              "resolved; retry later, or send the scenario itself"));
    }
    if (stored.value->kind != kind) {
        return base_problem(
            concat(api::quoted_for_message(name), " is a stored ", mill ? "stand scenario" : "mill",
                   ", not a ", noun),
            mill ? concat("names a stored stand scenario; a mill's analysis (", analysis->name,
                          ") takes a stored mill (GET /v1/mills lists them)")
                 : std::string("names a stored mill; a stand's analysis takes a stored scenario "
                               "(GET /v1/scenarios lists them), a mill's is POST /v1/tandem"));
    }
    auto parsed = api::parse_json_text(stored.value->body);
    if (std::holds_alternative<api::Problem>(parsed)) {
        // Only this service writes the table, always valid JSON: a corrupted row is a fault.
        return problem_outcome(api::make_problem(api::ProblemCode::internal,
                                                 concat("stored scenario ", name, " is not JSON")));
    }
    json document = std::move(std::get<json>(parsed));
    const json stored_document = document;
    // null and absent are the same patch: nothing changes.
    if (const auto patch = request.find(member); patch != request.end() && !patch->is_null())
        document.merge_patch(*patch);
    // A speed limit of a calibrated stand carries the stand's own uncertainty (docs/model.md
    // §13.3): its stored posterior, unless the request gives one (null: none) or its patch moves
    // a field the posterior describes (then it would describe another stand).
    if (analysis != nullptr && analysis->name == "speed_limit" &&
        !stored.value->posterior.empty()) {
        json& options = request["options"];
        if (options.is_null()) options = json::object();
        if (options.is_object() && !options.contains("posterior")) {
            const json posterior = json::parse(stored.value->posterior);
            bool centred = true;
            for (const json& p : posterior.value("parameters", json::array())) {
                const json::json_pointer at(p.value("field", ""));
                centred = centred && stored_document.contains(at) && document.contains(at) &&
                          stored_document[at] == document[at];
            }
            if (centred) options["posterior"] = posterior;
        }
    }
    request[std::string(member)] = std::move(document);
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
