#pragma once
// The result of a batch (docs/http-api.md, "Batches"): one headline row per item, in the items'
// order, each carrying its own answer's key figures or its own problem, so that a coil that
// cannot be computed never hides the others. The row is the batch's point document (a job
// splits a batch into chunks of items, service/chunked.h): the result is the rows in order with
// their counts.

#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "api/result_table.h"

namespace rollgap::api {

// The most items one batch takes (10,000 coils: a week of a 5-stand mill's production).
inline constexpr std::size_t max_batch_items = 10000;
// The longest label (a coil id, an MES key).
inline constexpr std::size_t max_batch_label = 128;

// The key figures of one item's answer (its "result"): for speed_limit the advised speed, the
// binding limit, the window, the margins at the operating speed and the critical speed with its
// uncertainty; for any other analysis the result's scalars to two levels as they are (a nested
// one named "critical_speed/critical_speed_m_per_s"). Flat:
// every value a number, string, boolean or null (a CSV row).
nlohmann::json batch_headline(std::string_view analysis, const nlohmann::json& result);

// An item's row: {index, label, status, base, headline, problem}. `answer` is the item's
// answer document ({analysis, scenario|tandem, options, result, base?}) or, when `failed`, its
// problem details.
nlohmann::json batch_row(std::size_t index, std::string_view label, bool failed,
                         const nlohmann::json& answer);

// The result from all rows in order: {analysis, items_total, succeeded, failed, items}.
nlohmann::json batch_result_json(std::string_view analysis, nlohmann::json rows);

// The components of the result (BatchResult, BatchItem) and its CSV table "items": one row per
// item, index, label, status and base first, then the headline's members (the union over the
// rows, in order of first appearance), then the problem's type, title and detail.
std::vector<ResultSchema> batch_result_schemas();
std::span<const CsvTable> batch_csv_tables();

}  // namespace rollgap::api
