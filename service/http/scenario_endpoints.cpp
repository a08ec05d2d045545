#include "service/http/scenario_endpoints.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <cstdint>
#include <ctime>
#include <optional>
#include <vector>

#include "api/field_errors.h"
#include "api/plant_units.h"
#include "api/request_json.h"
#include "api/scenario_json.h"
#include "api/tandem_json.h"
#include "service/evaluate.h"
#include "api/text.h"
#include "service/http/responses.h"
#include "service/http/scenario_base.h"

namespace rollgap::service::http {

using api::concat;
using nlohmann::json;
using store::StoreStatus;

// The entity tags of an If-Match or If-None-Match header (RFC 9110 §8.8.3, §13.1.1-2). A
// version is the ETag "<version>"; anything else this service never issued matches nothing.
// Declared in the header for expected_version().
struct EntityTags {
    bool present = false;
    bool any = false;                  // "*"
    std::vector<std::int64_t> strong;  // "7"
    std::vector<std::int64_t> weak;    // W/"7": matches only in the weak comparison

    bool matches(std::int64_t version, bool weak_comparison) const {
        const auto in = [version](const std::vector<std::int64_t>& list) {
            return std::find(list.begin(), list.end(), version) != list.end();
        };
        return in(strong) || (weak_comparison && in(weak));
    }
};

namespace {

constexpr std::string_view store_down = "the scenario store is unavailable; retry later";

std::optional<std::int64_t> quoted_version(std::string_view tag) {
    if (tag.size() < 3 || tag.front() != '"' || tag.back() != '"') return std::nullopt;
    const std::string_view digits = tag.substr(1, tag.size() - 2);
    std::int64_t version = 0;
    const auto [end, error] =
        std::from_chars(digits.data(), digits.data() + digits.size(), version);
    if (error != std::errc() || end != digits.data() + digits.size() || version < 1)
        return std::nullopt;
    return version;
}

EntityTags entity_tags(const httplib::Request& request, const char* header) {
    EntityTags tags;
    if (!request.has_header(header)) return tags;
    tags.present = true;
    const std::string value = request.get_header_value(header);
    std::string_view rest = value;
    while (!rest.empty()) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = trim(rest.substr(0, comma));
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
        if (item == "*") {
            tags.any = true;
        } else if (item.starts_with("W/")) {
            if (auto version = quoted_version(item.substr(2))) tags.weak.push_back(*version);
        } else if (auto version = quoted_version(item)) {
            tags.strong.push_back(*version);
        }
    }
    return tags;
}

// RFC 9110 §13.2.2 for a write: If-Match first, then If-None-Match, against the current
// version (nothing: no such scenario).
bool preconditions_hold(const EntityTags& if_match, const EntityTags& if_none_match,
                        std::optional<std::int64_t> current) {
    if (if_match.present && !(current && (if_match.any || if_match.matches(*current, false)))) {
        return false;
    }
    if (if_none_match.present && current &&
        (if_none_match.any || if_none_match.matches(*current, true))) {
        return false;
    }
    return true;
}

std::string etag(std::int64_t version) { return concat("\"", std::to_string(version), "\""); }

std::string rfc3339(store::Millis millis) {
    const std::time_t seconds = static_cast<std::time_t>(millis / 1000);
    std::tm utc{};
    gmtime_r(&seconds, &utc);
    char text[32];
    const std::size_t length = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
    char fraction[8];
    std::snprintf(fraction, sizeof fraction, ".%03dZ", static_cast<int>(millis % 1000));
    return concat(std::string_view(text, length), fraction);
}

// Last-Modified: an IMF-fixdate (RFC 9110 §5.6.7).
std::string http_date(store::Millis millis) {
    const std::time_t seconds = static_cast<std::time_t>(millis / 1000);
    std::tm utc{};
    gmtime_r(&seconds, &utc);
    char text[40];
    const std::size_t length = std::strftime(text, sizeof text, "%a, %d %b %Y %H:%M:%S GMT", &utc);
    return std::string(text, length);
}

// The stored posterior restricted to the fields `options.parameters` fits without a prior of
// its own (the marginal of a Gaussian is its sub-block); null when none of them.
json marginal_prior(const json& posterior, const json& options) {
    if (!options.is_object() || !options.contains("parameters") ||
        !options["parameters"].is_array() || !posterior.is_object())
        return nullptr;
    std::vector<std::string> fitted;
    for (const json& p : options["parameters"]) {
        if (!p.is_object() || !p.contains("field") || !p["field"].is_string()) continue;
        if (p.contains("prior") && !p["prior"].is_null()) continue;
        fitted.push_back(p["field"].get<std::string>());
    }
    const json& parameters = posterior.value("parameters", json::array());
    const json& correlation = posterior.value("correlation", json::array());
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < parameters.size(); ++k) {
        if (std::find(fitted.begin(), fitted.end(), parameters[k].value("field", "")) !=
            fitted.end())
            kept.push_back(k);
    }
    if (kept.empty()) return nullptr;
    json out = {{"parameters", json::array()}, {"correlation", json::array()}};
    for (const std::size_t i : kept) {
        out["parameters"].push_back(parameters[i]);
        json row = json::array();
        for (const std::size_t k : kept) row.push_back(correlation.at(i).at(k));
        out["correlation"].push_back(std::move(row));
    }
    return out;
}

// What a stored version keeps of a calibration answer: each fitted field's value and standard
// error, and the correlation; "" when the fit has no statistics (a standard error is null).
std::string posterior_of(const json& result) {
    json parameters = json::array();
    for (const json& p : result.value("parameters", json::array())) {
        if (!p.contains("standard_error") || !p["standard_error"].is_number()) return "";
        parameters.push_back({{"field", p["field"]},
                              {"unit", p["unit"]},
                              {"value", p["value"]},
                              {"standard_error", p["standard_error"]}});
    }
    if (parameters.empty()) return "";
    return dump(json{{"parameters", std::move(parameters)},
                     {"correlation", result.value("correlation", json::array())}});
}

}  // namespace

ScenarioEndpoints::ScenarioEndpoints(ServiceState& state, store::StoredKind kind)
    : state_(state), kind_(kind),
      prefix_(kind == store::StoredKind::mill ? mill_prefix : scenario_prefix),
      noun_(kind == store::StoredKind::mill ? "mill" : "scenario"),
      default_text_(dump(kind == store::StoredKind::mill ? api::default_tandem_json()
                                                         : api::default_scenario_json())) {}

// 422 for a name in the path that cannot be stored (the pattern, or `default`).
bool ScenarioEndpoints::refuse_name(const std::string& name, httplib::Response& response) const {
    auto error = api::stored_scenario_name_error(name, "/name");
    if (!error) return false;
    error->detail = concat("the {name} of the path: ", error->detail);
    set_problem(response, api::ProblemCode::invalid_request,
                name == api::reserved_scenario_name
                    ? concat("'", api::reserved_scenario_name, "' is the built-in default ", noun_,
                             ": it can be read, not stored or deleted")
                    : concat(api::quoted_for_message(name), " is not a ", noun_, " name"),
                {std::move(*error)});
    return true;
}

void ScenarioEndpoints::precondition_failed(httplib::Response& response,
                                            const std::string& name) const {
    set_problem(response, api::ProblemCode::precondition_failed,
                concat(noun_, " ", name,
                       ": If-Match or If-None-Match does not hold for its current version (it "
                       "changed, was created or deleted since); GET it again"));
}

void ScenarioEndpoints::not_found(const std::string& name, httplib::Response& response) const {
    // A name holds one kind at a time; one of the other kind is in the other collection.
    set_problem(response, api::ProblemCode::not_found,
                concat("no stored ", noun_, " ", name, "; GET ",
                       prefix_.substr(0, prefix_.size() - 1), " lists them"));
}

bool ScenarioEndpoints::accepted(const api::FieldErrors& errors, const std::string& what,
                                 httplib::Response& response) const {
    if (errors.empty()) return true;
    set_problem(response,
                errors.to_problem(api::ProblemCode::invalid_scenario,
                                  concat(std::to_string(errors.size()),
                                         errors.size() == 1 ? " violation" : " violations",
                                         " in the ", what, "; nothing was stored")));
    return false;
}

bool ScenarioEndpoints::canonical_body(json& body, httplib::Response& response) const {
    // Plant units (api/plant_units.h) in canonical keys before the body is merged or read.
    api::FieldErrors errors;
    if (kind_ == store::StoredKind::mill) {
        api::canonicalise_tandem_patch(body, "", errors);
    } else {
        api::canonicalise_scenario_patch(body, "", errors);
    }
    return accepted(errors, concat(noun_, "'s plant units"), response);
}

bool ScenarioEndpoints::resolve_body(const json& body, json& resolved,
                                     httplib::Response& response) const {
    // The same reading as an analysis' "scenario" or "tandem": a merge patch onto the default,
    // every violation reported with its pointer (into this body), bound and unit. Nothing is
    // stored unless the whole document is valid.
    api::FieldErrors errors;
    if (kind_ == store::StoredKind::mill) {
        const core::Mill mill = api::mill_from_patch(body, "", errors);
        if (errors.empty()) resolved = api::resolved_tandem_json(mill);
    } else {
        const core::Scenario scenario = api::scenario_from_patch(body, "", errors);
        if (errors.empty()) resolved = api::resolved_scenario_json(scenario);
    }
    return accepted(errors, std::string(noun_), response);
}

bool ScenarioEndpoints::expected_version(store::JobStore& store, const std::string& name,
                                         const EntityTags& if_match,
                                         const EntityTags& if_none_match,
                                         std::optional<std::int64_t>& expected,
                                         httplib::Response& response) {
    if (if_match.present && !if_match.any && if_match.strong.size() == 1 &&
        !if_none_match.present) {
        expected = if_match.strong.front();  // the usual edit: one version, checked by the store
        return true;
    }
    // No precondition, or If-None-Match: * (the store refuses a stored name without a version).
    if (!if_match.present && (!if_none_match.present || if_none_match.any)) return true;
    // "*", lists, or both headers: compare with the current version, then write over exactly
    // that version (the store refuses if it changed in between).
    auto current = store.get_scenario(name);
    state_.store.report(current.status);
    if (current.status == StoreStatus::unavailable) {
        state_.store_unavailable(response, std::string(store_down));
        return false;
    }
    // A name of the other kind is no version of this collection's document.
    const std::optional<std::int64_t> version = current.ok() && current.value->kind == kind_
                                                    ? std::optional(current.value->version)
                                                    : std::nullopt;
    if (!preconditions_hold(if_match, if_none_match, version)) {
        precondition_failed(response, name);
        return false;
    }
    expected = version;
    return true;
}

void ScenarioEndpoints::get_or_delete(const httplib::Request& request, const std::string& client,
                                      httplib::Response& response) {
    if (!request.path.starts_with(prefix_)) {
        list(request, response);
        return;
    }
    std::string name = request.path.substr(prefix_.size());
    if (kind_ == store::StoredKind::stand && name.ends_with(calibrate_suffix)) {
        name.resize(name.size() - calibrate_suffix.size());
        posterior(name, response);
        return;
    }
    if (request.method == "DELETE") {
        remove(name, request, client, response);
    } else {
        get(name, request, response);
    }
}

void ScenarioEndpoints::list(const httplib::Request& request, httplib::Response& response) {
    store::ScenarioQuery query;
    query.kind = kind_;
    query.limit = default_page;
    if (!read_page_limit(request, response, max_page, query.limit)) return;
    if (request.has_param("cursor")) query.cursor = request.get_param_value("cursor");
    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    auto listed = store->list_scenario_page(query);
    state_.store.report(listed.status);
    if (listed.status == StoreStatus::invalid) {
        invalid_parameter(response, "cursor", "the next_cursor of an earlier page");
        return;
    }
    if (!listed.ok()) return state_.store_unavailable(response, std::string(store_down));
    json scenarios = json::array();
    for (const store::StoredScenario& scenario : listed.value->scenarios) {
        scenarios.push_back({{"name", scenario.name},
                             {"version", scenario.version},
                             {"updated_at", rfc3339(scenario.updated_ms)},
                             {"author", scenario.author}});
    }
    json body = {{kind_ == store::StoredKind::mill ? "mills" : "scenarios", std::move(scenarios)}};
    if (listed.value->next_cursor) body["next_cursor"] = *listed.value->next_cursor;
    set_json(response, 200, body, "application/json");
}

void ScenarioEndpoints::get(const std::string& name, const httplib::Request& request,
                            httplib::Response& response) {
    if (name == api::reserved_scenario_name) {  // never needs the store
        response.status = 200;
        response.set_content(default_text_, "application/json");
        return;
    }
    if (refuse_name(name, response)) return;
    std::optional<std::int64_t> version;
    if (request.has_param("version")) {
        const std::string text = request.get_param_value("version");
        std::int64_t value = 0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() || value < 1) {
            invalid_parameter(response, "version", "a version number, 1 or more (the ETag's)");
            return;
        }
        version = value;
    }
    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    auto found = store->get_scenario(name, version);
    state_.store.report(found.status);
    if (!found.ok() && found.status != StoreStatus::not_found)
        return state_.store_unavailable(response, std::string(store_down));
    if (found.status == StoreStatus::not_found || found.value->kind != kind_) {
        if (version) {
            set_problem(
                response, api::ProblemCode::not_found,
                concat("no version ", std::to_string(*version), " of the stored ", noun_, " ", name,
                       ": the last ", std::to_string(store::StoreLimits{}.scenario_history),
                       " versions of a name are kept, and a delete is no document"));
            return;
        }
        not_found(name, response);
        return;
    }
    response.status = 200;
    response.set_header("ETag", etag(found.value->version));
    // Who wrote this version and when; the body stays the scenario itself.
    response.set_header("Last-Modified", http_date(found.value->updated_ms));
    response.set_header("Rollgap-Author", found.value->author);
    response.set_content(found.value->body, "application/json");
}

void ScenarioEndpoints::remove(const std::string& name, const httplib::Request& request,
                               const std::string& client, httplib::Response& response) {
    if (refuse_name(name, response)) return;
    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    std::optional<std::int64_t> expected;
    if (!expected_version(*store, name, entity_tags(request, "If-Match"), {}, expected, response))
        return;
    const StoreStatus status = store->delete_scenario(name, expected, client, kind_);
    state_.store.report(status);
    switch (status) {
        case StoreStatus::ok: response.status = 204; return;
        case StoreStatus::not_found: not_found(name, response); return;
        case StoreStatus::conflict: precondition_failed(response, name); return;
        default: state_.store_unavailable(response, std::string(store_down)); return;
    }
}

void ScenarioEndpoints::put(const httplib::Request& request, json body, const std::string& client,
                            httplib::Response& response) {
    const std::string name = request.path.substr(prefix_.size());
    if (refuse_name(name, response)) return;
    if (!canonical_body(body, response)) return;
    json resolved;
    if (!resolve_body(body, resolved, response)) return;

    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    const EntityTags if_match = entity_tags(request, "If-Match");
    const EntityTags if_none_match = entity_tags(request, "If-None-Match");
    std::optional<std::int64_t> expected;
    if (!expected_version(*store, name, if_match, if_none_match, expected, response)) return;
    auto written = store->put_scenario(name, dump(resolved), expected, client, kind_);
    state_.store.report(written.status);
    switch (written.status) {
        case StoreStatus::ok: break;
        case StoreStatus::conflict:
            if (written.detail == store::kind_conflict_detail) {
                set_problem(response, api::ProblemCode::conflict,
                            concat(api::quoted_for_message(name), " is a stored ",
                                   kind_ == store::StoredKind::mill ? "stand scenario" : "mill",
                                   ": a name holds one kind at a time; DELETE it there first or "
                                   "choose another name"));
            } else if (if_match.present || if_none_match.present) {
                precondition_failed(response, name);
            } else {
                set_problem(response, api::ProblemCode::precondition_required,
                            concat(noun_, " ", name,
                                   " exists: replacing it needs If-Match with the ETag of the "
                                   "version you edited (GET it), so that no other edit is lost"));
            }
            return;
        case StoreStatus::full:
            set_problem(response, api::ProblemCode::insufficient_storage,
                        concat("the store holds ", std::to_string(state_.config.max_scenarios),
                               " scenarios, its limit (--max-scenarios); DELETE one first"));
            return;
        case StoreStatus::invalid:
            // The store's own name rule; refuse_name() let it through, so say it plainly.
            set_problem(response, api::ProblemCode::invalid_request,
                        concat("the store refuses the name ", name));
            return;
        default: state_.store_unavailable(response, std::string(store_down)); return;
    }
    const bool created = written.value->created;
    response.set_header("ETag", etag(written.value->version));
    if (created) response.set_header("Location", concat(prefix_, name));
    set_json(response, created ? 201 : 200, resolved, "application/json");
}

std::optional<store::StoredScenario> ScenarioEndpoints::stored(store::JobStore& store,
                                                               const std::string& name,
                                                               httplib::Response& response) {
    auto found = store.get_scenario(name);
    state_.store.report(found.status);
    if (!found.ok() && found.status != StoreStatus::not_found) {
        state_.store_unavailable(response, std::string(store_down));
        return std::nullopt;
    }
    if (found.status == StoreStatus::not_found || found.value->kind != kind_) {
        not_found(name, response);
        return std::nullopt;
    }
    return std::move(*found.value);
}

void ScenarioEndpoints::patch(const httplib::Request& request, json body, const std::string& client,
                              httplib::Response& response) {
    const std::string name = request.path.substr(prefix_.size());
    if (refuse_name(name, response)) return;
    if (!body.is_object()) {
        set_problem(response, api::ProblemCode::invalid_request,
                    "a merge patch of a stored document is a JSON object",
                    {{"", concat("must be an object, not ", api::json_type_name(body)),
                      std::nullopt, std::nullopt}});
        return;
    }
    if (!canonical_body(body, response)) return;
    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    const std::optional<store::StoredScenario> current = stored(*store, name, response);
    if (!current) return;
    if (!preconditions_hold(entity_tags(request, "If-Match"), entity_tags(request, "If-None-Match"),
                            current->version)) {
        precondition_failed(response, name);
        return;
    }
    // RFC 7396 onto the stored document: the fields the patch does not name keep their values.
    json document = json::parse(current->body);
    document.merge_patch(body);
    json resolved;
    if (!resolve_body(document, resolved, response)) return;
    const std::string kept =
        posterior_still_centred(current->posterior, json::parse(current->body), resolved);
    auto written = store->put_scenario(name, dump(resolved), current->version, client, kind_, kept);
    state_.store.report(written.status);
    switch (written.status) {
        case StoreStatus::ok: break;
        case StoreStatus::conflict:  // written meanwhile: the patch was merged onto an old version
            precondition_failed(response, name);
            return;
        default: state_.store_unavailable(response, std::string(store_down)); return;
    }
    response.set_header("ETag", etag(written.value->version));
    set_json(response, 200, resolved, "application/json");
}

void ScenarioEndpoints::posterior(const std::string& name, httplib::Response& response) {
    if (refuse_name(name, response)) return;
    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    const std::optional<store::StoredScenario> found = stored(*store, name, response);
    if (!found) return;
    response.set_header("ETag", etag(found->version));
    set_json(
        response, 200,
        {{"name", name},
         {"version", found->version},
         {"updated_at", rfc3339(found->updated_ms)},
         {"author", found->author},
         {"posterior", found->posterior.empty() ? json(nullptr) : json::parse(found->posterior)}},
        "application/json");
}

void ScenarioEndpoints::calibrate(const httplib::Request& request, json body,
                                  const std::string& client, SteadyClock::time_point arrival,
                                  SyncDispatch& sync, httplib::Response& response) {
    const std::string path = request.path.substr(prefix_.size());
    const std::string name = path.substr(0, path.size() - calibrate_suffix.size());
    if (refuse_name(name, response)) return;
    if (!body.is_object()) {
        set_problem(response, api::ProblemCode::invalid_request,
                    "the body is {\"options\": {...}}, a calibration's options",
                    {{"", concat("must be an object, not ", api::json_type_name(body)),
                      std::nullopt, std::nullopt}});
        return;
    }
    for (const auto& [member, value] : body.items()) {
        if (member == "options") continue;
        set_problem(response, api::ProblemCode::invalid_request,
                    concat("the stored ", noun_,
                           " is the scenario calibrated; the body holds "
                           "its options only"),
                    {{concat("/", member), "not a member of this body: only \"options\"",
                      std::nullopt, std::nullopt}});
        return;
    }
    const EntityTags if_match = entity_tags(request, "If-Match");
    if (!if_match.present) {
        set_problem(response, api::ProblemCode::precondition_required,
                    concat("calibrating ", noun_, " ", name,
                           " stores a new version: send If-Match with the ETag of the version "
                           "you calibrate (GET it), so that no other edit is lost"));
        return;
    }
    const auto store = state_.store.get();
    if (!store) return state_.store_unavailable(response, std::string(store_down));
    const std::optional<store::StoredScenario> current = stored(*store, name, response);
    if (!current) return;
    if (!preconditions_hold(if_match, entity_tags(request, "If-None-Match"), current->version)) {
        precondition_failed(response, name);
        return;
    }
    json options = body.value("options", json::object());
    if (options.is_object() && !options.contains("joint_prior") && !current->posterior.empty()) {
        const json prior = marginal_prior(json::parse(current->posterior), options);
        if (!prior.is_null()) options["joint_prior"] = prior;
    }
    json analysis = {{"analysis", "calibrate"},
                     {"scenario", json::parse(current->body)},
                     {"options", std::move(options)}};
    auto prepared = service::prepare(analysis);
    if (auto* problem = std::get_if<Outcome>(&prepared)) {
        set_outcome(request, *problem, response);
        return;
    }
    const std::int64_t version = current->version;
    const std::string stored_body = current->body;
    sync.run(request, std::move(analysis), std::move(std::get<PreparedRequest>(prepared)), arrival,
             response,
             [this, name, version, client, stored_body](const Outcome& outcome,
                                                        httplib::Response& answer) {
                 json document = outcome.body;
                 const json& result = document["result"];
                 if (result.value("status", "") != "converged") {
                     // Nothing learnt that could be kept: answered, not stored.
                     document["stored"] = nullptr;
                     set_json(answer, 200, document, "application/json");
                     return;
                 }
                 json calibrated = json::parse(stored_body);
                 calibrated.merge_patch(result["calibrated_scenario"]);
                 json resolved;
                 if (!resolve_body(calibrated, resolved, answer)) return;
                 const auto target = state_.store.get();
                 if (!target) return state_.store_unavailable(answer, std::string(store_down));
                 auto written = target->put_scenario(name, dump(resolved), version, client, kind_,
                                                     posterior_of(result));
                 state_.store.report(written.status);
                 if (written.status == StoreStatus::conflict)
                     return precondition_failed(answer, name);
                 if (!written.ok())
                     return state_.store_unavailable(answer, std::string(store_down));
                 document["stored"] = {{"name", name}, {"version", written.value->version}};
                 answer.set_header("ETag", etag(written.value->version));
                 set_json(answer, 200, document, "application/json");
             });
}

}  // namespace rollgap::service::http
