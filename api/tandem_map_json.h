#pragma once
// Options and result of a mill map, the analysis `tandem_map` (docs/model.md §12.10): the mill's
// critical speeds, or its stability at its speed, over a grid of two numbers of its document.
//
// Options:
//   parameters      [rows, columns], each {"parameter", "values" | "range"}: a JSON pointer into
//                   the tandem document as a mill sweep's (api/tandem_sweep_json.h: a stand's
//                   field, a span length, a tension set point or all of them, the schedule, the
//                   mill speed) and its values as a sweep gives them; two different numbers
//   quantity        "critical_speed" (default) | "stability", as a mill sweep's
//   critical_speed  the search options over mill speeds (quantity critical_speed only)
//
// Each value is read back through the mill's validation on its own (a violation at
// /options/parameters/<k>/values/<i> or .../range, with the field's bound and unit), then each
// cell with both values set (the first failing cell reported at /options/parameters). The mill
// speed is an axis of stability maps only: the critical-speed search scans it itself. At most
// max_tandem_map_cells cells.

#include <array>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "api/field_errors.h"
#include "api/result_table.h"
#include "api/tandem_points.h"
#include "core/mill/mill.h"

namespace rollgap::api {

// A five-stand cell's critical speeds take seconds: 20 × 20 cells is a job of minutes.
inline constexpr int max_tandem_map_cells = 400;

struct TandemMapAxis {
    std::string parameter;  // "" when invalid
    Unit unit = units::one;
    std::vector<double> values;  // in the field's unit, as the client wrote them
    nlohmann::json resolved;     // the echo: {"parameter", "values" | "range"}
};

struct TandemMapPlan {
    std::array<TandemMapAxis, 2> axes;
    std::vector<core::Mill> cells;  // row-major; filled only for a valid request
    TandemPointSpec spec;
    nlohmann::json resolved_options;
};

TandemMapPlan tandem_map_plan_from_json(const nlohmann::json& options, const std::string& pointer,
                                        const core::Mill* valid_mill, FieldErrors& errors);

// The documents of cells [first, first + count) (row-major), as "cells" lists them; cancellation
// is polled between cells.
nlohmann::json tandem_map_cells_json(const TandemMapPlan& plan, std::size_t first,
                                     std::size_t count, const core::Control& control);

// The result from all cells' documents in order; chatter_type_changes from their chatter types.
nlohmann::json tandem_map_result_json(const TandemMapPlan& plan, nlohmann::json cells);

std::vector<ResultSchema> tandem_map_result_schemas();
std::span<const CsvTable> tandem_map_csv_tables();

}  // namespace rollgap::api
