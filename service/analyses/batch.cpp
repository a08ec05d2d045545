#include "service/analyses/batch.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "api/batch_json.h"
#include "api/field_errors.h"
#include "api/text.h"
#include "core/parallel_for.h"
#include "service/analyses/table.h"
#include "service/evaluate.h"

namespace rollgap::service {

using api::concat;
using nlohmann::json;

namespace {

// The batch as prepare_batch read it, shared by the chunks' computations.
struct Batch {
    const Analysis* inner = nullptr;
    std::string member;  // "scenario" or "tandem"
    json options;        // the batch's options as sent (items included)
};

const Analysis* read_inner(const json& options, const std::string& pointer,
                           api::FieldErrors& errors) {
    const auto found = options.find("analysis");
    const std::string at = concat(pointer, "/analysis");
    if (found == options.end()) {
        errors.add({at, "required: the analysis every item runs, e.g. \"speed_limit\"",
                    std::nullopt, std::nullopt});
        return nullptr;
    }
    const auto name = api::read_string(*found, at, errors);
    if (!name) return nullptr;
    const Analysis* inner = find_analysis(analyses(), *name);
    std::string runnable;
    for (const Analysis& row : analyses()) {
        if (row.subject() == Subject::batch || row.pointwise()) continue;
        runnable += concat(runnable.empty() ? "" : " | ", row.name);
    }
    if (inner == nullptr || inner->subject() == Subject::batch || inner->pointwise()) {
        errors.add(
            {at,
             inner == nullptr
                 ? concat("no analysis named ", api::quoted_for_message(*name))
                 : concat("'", *name,
                          inner->pointwise() ? "' splits into points of its own: send it as a job"
                                             : "' cannot be an item of a batch"),
             runnable, std::nullopt});
        return nullptr;
    }
    return inner;
}

// An object or null (absent) at `pointer`.
void check_patch(const json& parent, std::string_view member, const std::string& pointer,
                 api::FieldErrors& errors) {
    const auto found = parent.find(member);
    if (found == parent.end() || found->is_null()) return;
    api::require_object(*found, concat(pointer, "/", member), errors);
}

void check_base(const json& parent, const std::string& pointer, api::FieldErrors& errors) {
    const auto found = parent.find("base");
    if (found == parent.end() || found->is_null() || found->is_string()) return;
    // The resolved form, as the service writes it.
    if (found->is_object() && found->contains("name") && found->contains("version")) return;
    errors.add({concat(pointer, "/base"),
                concat("must name a stored ", parent.contains("tandem") ? "mill" : "scenario",
                       ", not ", api::json_type_name(*found)),
                std::string(api::stored_scenario_name_pattern), std::nullopt});
}

void check_item(const json& item, const std::string& pointer, const std::string& member,
                api::FieldErrors& errors) {
    if (!api::require_object(item, pointer, errors)) return;
    const std::array<std::string_view, 4> known{"label", member, "base", "options"};
    api::reject_unknown_fields(item, pointer, known, errors);
    const auto label = item.find("label");
    const std::string at = concat(pointer, "/label");
    if (label == item.end()) {
        errors.add({at, "required: the item's name in the rows, e.g. its coil id", std::nullopt,
                    std::nullopt});
    } else if (const auto text = api::read_string(*label, at, errors)) {
        if (text->empty() || text->size() > api::max_batch_label) {
            errors.add({at,
                        concat("must have 1 to ", std::to_string(api::max_batch_label),
                               " characters, not ", std::to_string(text->size())),
                        concat("[1, ", std::to_string(api::max_batch_label), "] characters"),
                        std::nullopt});
        }
    }
    check_patch(item, member, pointer, errors);
    check_patch(item, "options", pointer, errors);
    check_base(item, pointer, errors);
}

// The echo: everything but the items, which the rows list by index and label.
json resolved_echo(const json& options, std::size_t items) {
    json echo = json::object();
    for (const auto& [name, value] : options.items()) {
        if (name != "items") echo[name] = value;
    }
    echo["items_total"] = items;
    return echo;
}

// Where a violation of item `index`'s request (`pointer`, e.g. /scenario/strip/reduction) is
// in the batch: at the item's own member when the item gives the value, at the batch's shared
// one when only that does (/options/scenario/strip/reduction), else at the item.
std::string batch_pointer(const json& options, std::size_t index, const std::string& pointer) {
    const std::string item = concat("/options/items/", std::to_string(index));
    const std::size_t slash = pointer.find('/', 1);
    if (pointer.empty() || slash == std::string::npos) return item + pointer;
    const std::string member = pointer.substr(1, slash - 1);
    const std::string rest = pointer.substr(slash);
    if (member != "scenario" && member != "tandem" && member != "options") return item + pointer;
    const auto gives = [&rest](const json& parent, const std::string& name) {
        try {
            return parent.is_object() && parent.contains(name) &&
                   parent[name].contains(json::json_pointer(rest));
        } catch (const json::exception&) {
            return false;  // not a pointer into a JSON document: the item's
        }
    };
    const json& own = options["items"][index];
    // A resolved base holds the whole document: the batch's part is in it too.
    const bool resolved = own.contains("base") && own["base"].is_object();
    if (!gives(own, member) && !(resolved && member != "options") && gives(options, member))
        return concat("/options/", member, rest);
    return item + pointer;
}

// The pointers of the entries of `body[list]` (a problem's errors, an answer's warnings),
// rebased into the batch by batch_pointer.
void rebase_pointers(json& body, std::string_view list, const json& options, std::size_t index) {
    const auto entries = body.find(list);
    if (entries == body.end() || !entries->is_array()) return;
    for (json& entry : *entries) {
        if (entry.contains("pointer") && entry["pointer"].is_string())
            entry["pointer"] = batch_pointer(options, index, entry["pointer"]);
    }
}

json item_row(const Batch& batch, std::size_t index, const core::Control& control) {
    const json& item = batch.options["items"][index];
    const std::string label = item.value("label", std::string());
    const Outcome outcome = evaluate(batch_item_request(batch.options, index), control);
    // A stopped batch is cancelled, not a row that says so.
    if (outcome.problem == api::ProblemCode::cancelled && control.should_stop())
        throw AnalysisCancelled{};
    if (outcome.ok()) {
        // A coil's atypical value (a likely unit slip) is said in its row, pointing into the
        // batch as its problems do.
        json answer = outcome.body;
        rebase_pointers(answer, "warnings", batch.options, index);
        return api::batch_row(index, label, false, answer);
    }
    // The problem's pointers into the batch: /scenario/strip/reduction of item 7 is
    // /options/items/7/scenario/strip/reduction (the batch's shared parts merged under it).
    json problem = outcome.body;
    rebase_pointers(problem, "errors", batch.options, index);
    return api::batch_row(index, label, true, problem);
}

}  // namespace

json batch_item_request(const json& options, std::size_t index) {
    const Analysis* inner = find_analysis(analyses(), options.value("analysis", std::string()));
    const std::string member =
        inner != nullptr && inner->subject() == Subject::mill ? "tandem" : "scenario";
    const json& item = options["items"][index];
    json request = {{"analysis", options["analysis"]}};
    const json base = item.contains("base") && !item["base"].is_null()
                          ? item["base"]
                          : options.value("base", json());
    if (base.is_object()) {
        // Resolved by the service: the stored document with the batch's patch and the item's
        // merged onto it (service/http/scenario_base.h).
        request["base"] = base;
        request[member] = item.value(member, json::object());
    } else {
        if (!base.is_null()) request["base"] = base;  // unresolved: the facade says why
        // The batch's patch, then the item's: applied one after the other as RFC 7396 says.
        json patch = json::object();
        if (const auto shared = options.find(member);
            shared != options.end() && shared->is_object())
            patch.merge_patch(*shared);
        if (const auto own = item.find(member); own != item.end() && own->is_object())
            patch.merge_patch(*own);
        request[member] = std::move(patch);
    }
    json merged = options.contains("options") && options["options"].is_object() ? options["options"]
                                                                                : json::object();
    if (const auto own = item.find("options"); own != item.end() && own->is_object())
        merged.merge_patch(*own);
    // A batch wants each coil's headline; the sensitivities are asked for, not computed for
    // 10,000 coils by default (DECISIONS A).
    if (options["analysis"] == "speed_limit" && !merged.contains("what_to_change"))
        merged["what_to_change"] = false;
    request["options"] = std::move(merged);
    return request;
}

PreparedAnalysis prepare_batch(json options, const std::string& pointer, api::FieldErrors& errors) {
    if (!api::require_object(options, pointer, errors)) return {};
    const Analysis* inner = read_inner(options, pointer, errors);
    const std::string member =
        inner != nullptr && inner->subject() == Subject::mill ? "tandem" : "scenario";
    std::array<std::string_view, 5> known{"analysis", member, "base", "options", "items"};
    api::reject_unknown_fields(options, pointer, known, errors);
    check_patch(options, member, pointer, errors);
    check_patch(options, "options", pointer, errors);
    check_base(options, pointer, errors);

    const auto items = options.find("items");
    const std::string at = concat(pointer, "/items");
    const std::string bound = concat("[1, ", std::to_string(api::max_batch_items), "] items");
    if (items == options.end()) {
        errors.add(
            {at, "required: the items, each {label, scenario, options}", bound, std::nullopt});
    } else if (!items->is_array()) {
        errors.add({at, concat("must be an array, not ", api::json_type_name(*items)), bound,
                    std::nullopt});
    } else if (items->empty() || items->size() > api::max_batch_items) {
        errors.add(
            {at, concat("has ", std::to_string(items->size()), " items"), bound, std::nullopt});
    } else {
        for (std::size_t i = 0; i < items->size() && !errors.reporting_full(); ++i)
            check_item((*items)[i], concat(at, "/", std::to_string(i)), member, errors);
    }
    if (!errors.empty()) return {};

    const std::size_t count = items->size();
    json echo = resolved_echo(options, count);
    auto batch = std::make_shared<const Batch>(Batch{inner, member, std::move(options)});
    PointwiseRun points;
    points.count = static_cast<std::int64_t>(count);
    points.compute = [batch](std::int64_t begin, std::int64_t end, const core::Control& control) {
        const int n = static_cast<int>(end - begin);
        std::vector<json> rows(static_cast<std::size_t>(n));
        std::atomic<int> done{0};
        // The items side by side, each on one thread: independent coils parallelise perfectly,
        // better than the differences inside one item (docs/model.md §13.2).
        core::parallel_for(n, control.thread_budget(), control.executor, [&](int k) {
            if (control.should_stop()) return;
            rows[static_cast<std::size_t>(k)] =
                item_row(*batch, static_cast<std::size_t>(begin + k), control.nested(1));
            control.report(static_cast<double>(++done) / n);
        });
        throw_if_cancelled(control);
        json documents = json::array();
        for (json& row : rows) documents.push_back(std::move(row));
        return documents;
    };
    points.assemble = [batch](json documents) {
        return api::batch_result_json(batch->inner->name, std::move(documents));
    };
    return pointwise_analysis(std::move(echo), std::move(points));
}

}  // namespace rollgap::service
