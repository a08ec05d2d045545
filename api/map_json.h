#pragma once
// Options and result of a stability map (docs/model.md, "Stability maps"): the critical speed,
// its frequency and chatter type over a grid of two numeric scenario fields.
//
// Options:
//   parameters      [first, second], each {"parameter", "values" | "range"} as a sweep's
//                   (api/sweep_json.h); the first gives the rows, the second the columns
//   critical_speed  the search options of stability_json.h
//
// Each value is validated like its field (at /options/parameters/<k>/values/<i> or .../range);
// every cell's scenario (both values set) must also pass the cross-field rules. Bounded: at
// most max_map_cells cells and, as sweeps, max_sweep_scan_points scan speeds over all cells.

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/result_table.h"
#include "api/sweep_json.h"
#include "core/map.h"

namespace rollgap::api {

inline constexpr int max_map_cells = 2500;

struct MapPlan {
    std::array<SweepAxis, 2> axes;
    std::vector<core::Scenario> cells;  // row-major; filled only for a valid request
    core::CriticalSpeedOptions critical_speed;
    nlohmann::json resolved_options;
};

MapPlan map_plan_from_json(const nlohmann::json& options, const std::string& pointer,
                           const core::Scenario* valid_scenario, FieldErrors& errors);

// {"parameters": [{"parameter", "unit", "values"} × 2], "cells": [{"values": [first, second],
// "status", "critical_speed_m_per_s", "frequency_Hz", "chatter_type", "chatter_band"}] (row-major),
// "chatter_type_changes": [{"from": [first, second], "to": [...], "from_chatter_type",
// "to_chatter_type"}]} for neighbouring cells along either axis.
nlohmann::json map_json(const MapPlan& plan, const core::StabilityMap& map);

// map_json in two steps, so that cells computed apart (the chunks of a job, on any replica)
// assemble into exactly the document one run writes; map_json is these two steps.
// The documents of the cells first, first + 1, ... (row-major index, one per result), as
// "cells" lists them.
nlohmann::json map_cells_json(const MapPlan& plan,
                              const std::vector<core::CriticalSpeedResult>& results,
                              std::size_t first);
// The result from all cells' documents in order; chatter_type_changes from their chatter types.
nlohmann::json map_result_json(const MapPlan& plan, nlohmann::json cells);

// The tables that write it (api/result_table.h): their OpenAPI components, and the scalar
// members of a cell (the CSV columns after the two values).
std::vector<ResultSchema> map_result_schemas();
std::vector<std::string> map_cell_columns();

}  // namespace rollgap::api
