#pragma once
// What an analysis is: one row (Analysis, below) that the facade, the HTTP routes, the OpenAPI
// document, CSV, chunked jobs, the fuzz dictionary and the workbench are all derived from, and
// a function that reads its options and returns the computation to run. Reading is separate
// from running so that every violation of the scenario and of the options is reported together,
// before any physics runs, and so that a server can queue the computation with a deadline.
//
// Adding an analysis takes one row in service/analyses/table.cpp plus its own files:
//  - service/analyses/<name>.{h,cpp}: its prepare function (options read, the run captured);
//  - api/<name>_json.{h,cpp}: its options reader and result writer with the result's schema
//    components (api/result_table.h), and its CSV tables in api/csv.cpp if it has any;
//  - its scalar options (numbers, integers, booleans) as rows of api/option_table.cpp, listed
//    under its options component there: the reader reads them by row (OptionsReader::read) and
//    the document's schema of each is generated from the same row;
//  - in service/openapi.json: its request body, its path and its options component with the
//    compound members only (the row names them; the scalar options, the response, result and
//    CSV parts of the document are generated);
//  - `build/tools/fuzz_vocabulary fuzz` to regenerate the fuzz dictionary and seed requests;
//  - if the page shows it (on_page), its view in web/js/views.js, keyed by its name (the page
//    lists the rows from the OpenAPI document's x-rollgap-analyses; without a view it shows the
//    headline numbers only).
// tests/service/test_analysis_descriptor.cpp checks every row is reachable everywhere, and
// tests/service/test_options_contract.cpp that every bound the document states is enforced.

#include <concepts>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "api/field_errors.h"
#include "api/result_table.h"
#include "core/control.h"
#include "core/mill/mill.h"
#include "core/scenario.h"

namespace rollgap::service {

// Thrown by a run that core reports as cancelled (its Control said stop): the facade turns it
// into the problem `cancelled`. A result with a "cancelled" status is never returned.
struct AnalysisCancelled {};

// For runs: after a core call that may have stopped early, so that a partly computed result
// (a sweep whose last points say "cancelled") is never returned as if it were complete.
inline void throw_if_cancelled(const core::Control& control) {
    if (control.should_stop()) throw AnalysisCancelled{};
}

// The same after a core call that returns one result per point (a sweep, a map): a point core
// marks "cancelled" was never computed.
template <class Results>
void throw_if_cancelled(const core::Control& control, const Results& results) {
    throw_if_cancelled(control);
    for (const auto& result : results) {
        if (result.status == decltype(result.status)::cancelled) throw AnalysisCancelled{};
    }
}

// The computation of a prepared analysis: the "result" member from the caller's Control
// (cancellation, progress). A computation that cannot be stopped may ignore the Control and be
// written as a function of nothing.
class AnalysisRun {
public:
    AnalysisRun() = default;

    template <class Run>
    requires std::invocable<Run&, const core::Control&> AnalysisRun(Run run)
        : run_(std::move(run)) {}  // NOLINT(google-explicit-constructor)

    template <class Run>
    requires(!std::invocable<Run&, const core::Control&> && std::invocable<Run&>)
        AnalysisRun(Run run)  // NOLINT(google-explicit-constructor)
        : run_([run = std::move(run)](const core::Control&) mutable {
              return nlohmann::json(run());
          }) {}

    nlohmann::json operator()(const core::Control& control = {}) const { return run_(control); }
    explicit operator bool() const { return static_cast<bool>(run_); }

private:
    std::function<nlohmann::json(const core::Control&)> run_;
};

// An analysis whose result lists independent points (a sweep's values, a map's cells), run in
// two steps so that a job can spread its points over workers on any replica: `compute` writes
// the documents of points [begin, end) (a JSON array, one per point, as the result lists them),
// `assemble` writes the "result" member from all points' documents in order, deriving whatever
// depends on neighbours (chatter-type changes) from the documents. The analysis's own `run` is
// assemble(compute(0, count)), so a result assembled from chunks is the single run's by
// construction.
struct PointwiseRun {
    std::int64_t count = 0;
    std::function<nlohmann::json(std::int64_t begin, std::int64_t end, const core::Control&)>
        compute;  // throws AnalysisCancelled like a run
    std::function<nlohmann::json(nlohmann::json documents)> assemble;
};

struct PreparedAnalysis {
    nlohmann::json resolved_options;  // the options as applied, echoed with the result
    AnalysisRun run;                  // computes the "result" member; may take a while
    std::optional<PointwiseRun> points = std::nullopt;  // set iff the result splits into points
};

// A pointwise analysis prepared: its run is all points computed and assembled in one go.
inline PreparedAnalysis pointwise_analysis(nlohmann::json resolved_options, PointwiseRun points) {
    AnalysisRun run = [points](const core::Control& control) {
        return points.assemble(points.compute(0, points.count, control));
    };
    return {std::move(resolved_options), std::move(run), std::move(points)};
}

// Reads `options` strictly (violations under `options_pointer`) and captures what `run` needs.
// Must not compute. `errors` holds the scenario's violations when prepare is called, so the
// scenario is valid iff `errors` is empty on entry; rules that combine the options with the
// scenario run only then.
using PrepareAnalysis = PreparedAnalysis (*)(const core::Scenario& scenario,
                                             const nlohmann::json& options,
                                             const std::string& options_pointer,
                                             api::FieldErrors& errors);

// The same for an analysis of a tandem mill (docs/model.md §12): the request's "tandem" read
// into `mill`, its violations in `errors` on entry.
using PrepareMillAnalysis = PreparedAnalysis (*)(const core::Mill& mill,
                                                 const nlohmann::json& options,
                                                 const std::string& options_pointer,
                                                 api::FieldErrors& errors);

// A batch of another analysis' requests (docs/http-api.md, "Batches"): the request has no
// subject of its own; its options list the items, each a stand or a mill with options. Reads
// the options' shape only (a batch of 10,000 items is prepared on every replica that runs a
// chunk of it): an item's own violations are its row's problem, computed with the item. Takes
// the options by value: a batch of 10,000 items is kept once, not copied.
using PrepareBatchAnalysis = PreparedAnalysis (*)(nlohmann::json options,
                                                  const std::string& options_pointer,
                                                  api::FieldErrors& errors);

// What an analysis takes: one stand (the request's "scenario"), a mill ("tandem"), or a batch
// of items (neither: the items are in its options).
enum class Subject { stand, mill, batch };

// An options component of the OpenAPI document whose "default"s are those an analysis resolves
// from `minimal_options` (the defaults live in core; the document shows them).
struct OptionsDefaults {
    std::string_view schema;           // the component in openapi.json
    std::string_view minimal_options;  // JSON: the least options object the analysis accepts
    std::string_view member = "";      // the defaults are this member of the resolved options
};

// One analysis, everything the service says about it in one row.
struct Analysis {
    std::string_view name;     // the request's "analysis"
    std::string_view label;    // a short title: the workbench's tab and report heading
    std::string_view summary;  // one line for --help and the documentation
    PrepareAnalysis prepare;
    std::string_view path = "";  // its synchronous HTTP route (POST)
    // OpenAPI components: the answer {analysis, scenario, options, result} (generated), the
    // options (openapi.json) and the result (from the result tables, `result_schemas`).
    std::string_view response_schema = "";
    std::string_view options_schema = "";
    std::string_view result_schema = "";
    std::vector<api::ResultSchema> (*result_schemas)() = nullptr;  // the result's components
    std::span<const OptionsDefaults> options_defaults = {};        // components given core defaults
    // Option members whose default depends on the request: described, not stated, in OpenAPI.
    std::span<const std::string_view> request_dependent_options = {};
    // Its result's CSV tables (api/csv.h); nullptr: none, the result is not a sheet.
    std::span<const api::CsvTable> (*csv_tables)() = nullptr;
    // Pointwise (PointwiseRun: a job splits into chunks of points): the result components a
    // point can be (a running job's partial result lists them). Empty: runs whole.
    std::span<const std::string_view> point_components = {};
    bool on_page = true;  // the workbench page offers it (x-rollgap-analyses in OpenAPI)
    // A mill's analysis: `prepare` is nullptr and this reads its options (Subject::mill).
    PrepareMillAnalysis prepare_mill = nullptr;
    // A batch (Subject::batch): `prepare` and `prepare_mill` are nullptr and this reads its
    // options. Its route submits a job (202) instead of answering synchronously.
    PrepareBatchAnalysis prepare_batch = nullptr;

    Subject subject() const {
        return prepare_batch != nullptr  ? Subject::batch
               : prepare_mill != nullptr ? Subject::mill
                                         : Subject::stand;
    }

    bool pointwise() const { return !point_components.empty(); }
    std::span<const api::CsvTable> tables() const {
        return csv_tables == nullptr ? std::span<const api::CsvTable>() : csv_tables();
    }
};

}  // namespace rollgap::service
