#include "service/http/scenario_base.h"

#include <functional>
#include <map>
#include <string>
#include <variant>

#include "api/batch_json.h"
#include "api/json_text.h"
#include "api/request_json.h"
#include "api/tandem_json.h"
#include "api/text.h"
#include "service/analyses/table.h"
#include "service/http/responses.h"

namespace rollgap::service::http {

using api::concat;
using nlohmann::json;

namespace {

// One stored document as the store answered for a name (a batch asks once per name).
using Lookup = std::function<store::Result<store::StoredScenario>(const std::string&)>;

// What resolving one "base" came to: nothing wrong, a violation at the base's pointer (422), or
// another answer (503: the store; 500: a corrupted row).
using Resolution = std::variant<std::monostate, api::FieldError, Outcome>;

api::FieldError base_error(const std::string& pointer, std::string error) {
    return {pointer, std::move(error), std::string(api::stored_scenario_name_pattern),
            std::nullopt};
}

// `request`'s "base" (a name) resolved through `lookup`: the stored document, the request's
// subject patch merged onto it and then `then_patch` (a batch item's own patch, after the
// batch's shared one), the request rewritten to the resolved form. Violations at `pointer`.
Resolution resolve_one(json& request, const Lookup& lookup, const json* then_patch,
                       const std::string& pointer) {
    const json& found = request["base"];
    // A client names a stored scenario; the resolved {"name", "version"} form is what this
    // function writes, never something a client may claim.
    if (!found.is_string())
        return base_error(pointer, concat("must be a string, not ", api::json_type_name(found)));
    const std::string name = found.get<std::string>();
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
    if (auto error = api::stored_scenario_name_error(name, pointer)) return std::move(*error);

    const auto stored = lookup(name);
    if (stored.status == store::StoreStatus::unavailable && stored.detail == "no store") {
        return problem_outcome(
            api::make_problem(api::ProblemCode::store_unavailable,
                              "the scenario store is unavailable, so \"base\" cannot be "
                              "resolved; retry later, or send the scenario itself"));
    }
    if (stored.status == store::StoreStatus::not_found) {
        return base_error(
            pointer, concat("names no stored ", noun, " ", api::quoted_for_message(name), "; GET ",
                            mill ? "/v1/mills" : "/v1/scenarios", " lists them"));
    }
    if (!stored.ok()) {
        return problem_outcome(
            api::make_problem(api::ProblemCode::store_unavailable,
                              "the scenario store did not answer, so \"base\" cannot be "
                              "resolved; retry later, or send the scenario itself"));
    }
    if (stored.value->kind != kind) {
        return base_error(
            pointer,
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
    if (then_patch != nullptr && !then_patch->is_null()) document.merge_patch(*then_patch);
    // A speed limit of a calibrated stand carries the stand's own uncertainty (docs/model.md
    // §13.3): its stored posterior, unless the request gives one (null: none) or its patch moves
    // a field the posterior describes (then it would describe another stand).
    if (analysis != nullptr && analysis->name == "speed_limit" &&
        !stored.value->posterior.empty()) {
        json& options = request["options"];
        if (options.is_null()) options = json::object();
        if (options.is_object() && !options.contains("posterior")) {
            const std::string kept =
                posterior_still_centred(stored.value->posterior, stored_document, document);
            if (!kept.empty()) options["posterior"] = json::parse(kept);
        }
    }
    request[std::string(member)] = std::move(document);
    request["base"] = api::scenario_base_json({name, stored.value->version});
    return std::monostate{};
}

// A mill's stands that name a stored stand (docs/http-api.md, "Stored stands in a mill"):
// "<at>/stands/i/base": "<name>" becomes that stored stand's scenario without the fields the
// mill gives every stand, the stand's own patch merged over it, and "base": {"name", "version"}.
// Violations go to `errors` (every one at once); a store that fails is the returned outcome.
// `posteriors` gets, per stand, the stored posterior of a resolved stand while it still
// describes the stand (none of its fields the mill's, none moved by the patch), else null; it
// stays empty when no stand was resolved with one.
std::optional<Outcome> resolve_stands(json& tandem, const std::string& at, const Lookup& lookup,
                                      api::FieldErrors& errors, std::vector<json>& posteriors) {
    posteriors.clear();
    if (!tandem.is_object()) return std::nullopt;  // the facade reports it
    const auto stands = tandem.find("stands");
    // more stands than a mill has: the facade says so, no store is read for them
    if (stands == tandem.end() || !stands->is_array() ||
        stands->size() > static_cast<std::size_t>(core::max_mill_stands))
        return std::nullopt;
    const bool speeds_mode = tandem.value("mode", json()) == "speeds";
    std::vector<json> found_posteriors(stands->size());
    bool any_posterior = false;
    for (std::size_t i = 0; i < stands->size(); ++i) {
        json& stand = (*stands)[i];
        if (!stand.is_object()) continue;  // the facade reports it
        const auto found = stand.find("base");
        if (found == stand.end() || found->is_null()) continue;
        const std::string pointer = concat(at, "/stands/", std::to_string(i), "/base");
        // A client names a stored stand; the resolved {"name", "version"} form is what this
        // function writes, never something a client may claim (as for the request's "base").
        if (!found->is_string()) {
            errors.add(base_error(pointer, concat("must be the name of a stored stand scenario "
                                                  "(a string), not ",
                                                  api::json_type_name(*found))));
            continue;
        }
        const std::string name = found->get<std::string>();
        if (auto error = api::stored_scenario_name_error(name, pointer)) {
            errors.add(std::move(*error));
            continue;
        }
        const auto stored = lookup(name);
        if (stored.status == store::StoreStatus::not_found) {
            errors.add(
                base_error(pointer, concat("names no stored stand ", api::quoted_for_message(name),
                                           "; GET /v1/scenarios lists them")));
            continue;
        }
        if (!stored.ok()) {
            return problem_outcome(api::make_problem(
                api::ProblemCode::store_unavailable,
                "the scenario store did not answer, so a stand's \"base\" cannot be resolved; "
                "retry later, or send the stand itself"));
        }
        if (stored.value->kind != store::StoredKind::stand) {
            errors.add(base_error(pointer,
                                  "names a stored mill; a mill's stand takes a stored "
                                  "stand scenario (GET /v1/scenarios lists them)"));
            continue;
        }
        auto parsed = api::parse_json_text(stored.value->body);
        if (std::holds_alternative<api::Problem>(parsed)) {
            return problem_outcome(api::make_problem(
                api::ProblemCode::internal, concat("stored scenario ", name, " is not JSON")));
        }
        const json stored_stand =
            api::without_mill_owned_fields(std::move(std::get<json>(parsed)), speeds_mode);
        json document = stored_stand;
        json patch = stand;
        patch.erase("base");
        document.merge_patch(patch);
        // stored_stand lacks the mill's fields, so a posterior on one of them is not kept
        const std::string kept =
            posterior_still_centred(stored.value->posterior, stored_stand, document);
        if (!kept.empty()) {
            found_posteriors[i] = json::parse(kept);
            any_posterior = true;
        }
        document["base"] = api::scenario_base_json({name, stored.value->version});
        stand = std::move(document);
    }
    if (any_posterior) posteriors = std::move(found_posteriors);
    return std::nullopt;
}

// `options.posteriors` of a mill speed limit from its stored stands, unless the request gives
// its own (`also_given`: the batch's shared options gave them).
void take_stored_posteriors(json& options, const std::vector<json>& posteriors,
                            bool also_given = false) {
    if (posteriors.empty() || also_given) return;
    if (options.is_null()) options = json::object();
    if (options.is_object() && !options.contains("posteriors")) options["posteriors"] = posteriors;
}

const Analysis* analysis_of(const json& request) {
    const auto name = request.find("analysis");
    return name != request.end() && name->is_string()
               ? find_analysis(analyses(), name->get_ref<const std::string&>())
               : nullptr;
}

std::string stand_bases_detail(const api::FieldErrors& errors) {
    return concat(std::to_string(errors.size()),
                  errors.size() == 1 ? " stand base" : " stand bases",
                  " of the mill name no stored stand it can use");
}

// A mill analysis' request: its stands resolved (resolve_stands at /tandem), a speed limit's
// posteriors taken from them.
Resolution resolve_stand_bases(json& request, const Lookup& lookup) {
    const Analysis* analysis = analysis_of(request);
    if (analysis == nullptr || analysis->subject() != Subject::mill) return std::monostate{};
    const auto tandem = request.find("tandem");
    if (tandem == request.end()) return std::monostate{};
    api::FieldErrors errors;
    std::vector<json> posteriors;
    if (auto failed = resolve_stands(*tandem, "/tandem", lookup, errors, posteriors))
        return std::move(*failed);
    if (!errors.empty())
        return problem_outcome(
            errors.to_problem(api::ProblemCode::invalid_request, stand_bases_detail(errors)));
    if (analysis->name == "tandem_speed_limit")
        take_stored_posteriors(request["options"], posteriors);
    return std::monostate{};
}

// Looks names up in the store, reporting each answer to the store's health.
Lookup store_lookup(ServiceState& state) {
    return [&state](const std::string& name) -> store::Result<store::StoredScenario> {
        const auto store = state.store.get();
        if (!store) {
            state.store.report(store::StoreStatus::unavailable);
            return {store::StoreStatus::unavailable, std::nullopt, "no store"};
        }
        auto stored = store->get_scenario(name);
        state.store.report(stored.status);
        return stored;
    };
}

Outcome unresolved_outcome(Resolution resolution) {
    if (auto* outcome = std::get_if<Outcome>(&resolution)) return std::move(*outcome);
    api::FieldErrors errors;
    api::FieldError& error = std::get<api::FieldError>(resolution);
    const std::string detail = concat("\"base\" ", error.detail);
    errors.add(std::move(error));
    return problem_outcome(errors.to_problem(api::ProblemCode::invalid_request, detail));
}

// A batch's items (docs/http-api.md, "Batches"): each item's base, its own or the batch's,
// resolved like a request's, the batch's shared patch and then the item's merged onto the stored
// document. A resolved item holds its complete subject and base {"name", "version"}; a
// posterior the stored stand carries joins its options. Every unresolvable base is reported at
// once (422); each name is read from the store once per batch.
std::optional<Outcome> resolve_batch(json& request, ServiceState& state) {
    json& options = request["options"];
    if (!options.is_object()) return std::nullopt;  // the facade reports it
    const auto items = options.find("items");
    // Not a batch's items (the facade says why, 10,001 items included): no store is read for
    // them, so an oversized list cannot hold this thread over thousands of reads.
    if (items == options.end() || !items->is_array() || items->size() > api::max_batch_items)
        return std::nullopt;
    const json shared_base = options.value("base", json());
    const auto inner_name = options.find("analysis");
    const Analysis* inner =
        inner_name != options.end() && inner_name->is_string()
            ? find_analysis(analyses(), inner_name->get_ref<const std::string&>())
            : nullptr;
    if (inner == nullptr || inner->subject() == Subject::batch) return std::nullopt;
    const std::string member = inner->subject() == Subject::mill ? "tandem" : "scenario";

    std::map<std::string, store::Result<store::StoredScenario>> read;
    const Lookup plain = store_lookup(state);
    const Lookup cached = [&](const std::string& name) {
        auto found = read.find(name);
        if (found == read.end()) found = read.emplace(name, plain(name)).first;
        return found->second;
    };
    api::FieldErrors errors;
    const json shared_options = options.value("options", json::object());
    // A mill's stands that name stored stands: the batch's shared patch's once, each item's own
    // (RFC 7396: an item's "stands" replace the batch's whole); a speed limit's posteriors from
    // them unless the item or the batch gives its own.
    const bool of_mill = inner->subject() == Subject::mill;
    const bool takes_posteriors =
        inner->name == "tandem_speed_limit" &&
        !(shared_options.is_object() && shared_options.contains("posteriors"));
    std::vector<json> shared_posteriors;
    if (of_mill && options.contains(member)) {
        if (auto failed = resolve_stands(options[member], concat("/options/", member), cached,
                                         errors, shared_posteriors))
            return std::move(*failed);
    }
    for (std::size_t i = 0; i < items->size(); ++i) {
        json& item = (*items)[i];
        if (!item.is_object()) continue;  // the facade reports it
        if (of_mill) {
            const bool own_stands = item.contains(member) && item[member].is_object() &&
                                    item[member].contains("stands");
            std::vector<json> posteriors = own_stands ? std::vector<json>{} : shared_posteriors;
            if (own_stands) {
                if (auto failed = resolve_stands(
                        item[member], concat("/options/items/", std::to_string(i), "/", member),
                        cached, errors, posteriors))
                    return std::move(*failed);
            }
            if (takes_posteriors && !posteriors.empty())
                take_stored_posteriors(item["options"], posteriors);
        }
        const bool own = item.contains("base") && !item["base"].is_null();
        if (!own && shared_base.is_null()) continue;
        const std::string pointer =
            own ? concat("/options/items/", std::to_string(i), "/base") : "/options/base";
        if (!own && errors.has_error_at_or_below(pointer)) continue;
        json one = {{"analysis", inner->name}, {"base", own ? item["base"] : shared_base}};
        if (options.contains(member)) one[member] = options[member];
        json merged = shared_options.is_object() ? shared_options : json::object();
        if (const auto patch = item.find("options"); patch != item.end() && patch->is_object())
            merged.merge_patch(*patch);
        one["options"] = std::move(merged);
        const json then = item.value(member, json());
        Resolution resolution = resolve_one(one, cached, &then, pointer);
        if (auto* error = std::get_if<api::FieldError>(&resolution)) {
            errors.add(std::move(*error));
            continue;
        }
        if (auto* outcome = std::get_if<Outcome>(&resolution)) return std::move(*outcome);
        item["base"] = one["base"];
        item[member] = one[member];
        const bool asked = item.contains("options") && item["options"].is_object() &&
                           item["options"].contains("posterior");
        if (!asked && one["options"].contains("posterior")) {
            if (!item.contains("options") || !item["options"].is_object())
                item["options"] = json::object();
            item["options"]["posterior"] = one["options"]["posterior"];
        }
    }
    if (!errors.empty()) {
        return problem_outcome(errors.to_problem(
            api::ProblemCode::invalid_request,
            concat(std::to_string(errors.size()), errors.size() == 1 ? " base" : " bases",
                   " of the batch (its items' or their stands') name no stored document it can "
                   "use")));
    }
    // Every item that had the batch's base holds it resolved now.
    options.erase("base");
    return std::nullopt;
}

}  // namespace

std::string posterior_still_centred(const std::string& posterior, const json& before,
                                    const json& after) {
    if (posterior.empty()) return "";
    const json parsed = json::parse(posterior);
    for (const json& p : parsed.value("parameters", json::array())) {
        const json::json_pointer at(p.value("field", ""));
        if (!before.contains(at) || !after.contains(at) || before[at] != after[at]) return "";
    }
    return posterior;
}

std::optional<Outcome> resolve_base(json& request, ServiceState& state) {
    if (!request.is_object()) return std::nullopt;  // the facade reports it
    const auto analysis = request.find("analysis");
    if (analysis != request.end() && *analysis == "batch") return resolve_batch(request, state);
    const Lookup lookup = store_lookup(state);
    const auto found = request.find("base");
    if (found != request.end() && !found->is_null()) {
        Resolution resolution = resolve_one(request, lookup, nullptr, "/base");
        if (!std::holds_alternative<std::monostate>(resolution))
            return unresolved_outcome(std::move(resolution));
    }
    // the mill's own stands, stored ones among them, after the stored mill's patch is merged
    Resolution stands = resolve_stand_bases(request, lookup);
    if (auto* outcome = std::get_if<Outcome>(&stands)) return std::move(*outcome);
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
