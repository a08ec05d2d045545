#pragma once
// Options and results of a mill sweep, the analysis `tandem_sweep` (docs/model.md §12.10): one
// numeric value of the tandem document over a list or a range of values, the mill's critical
// speeds or its stability at its speed at each.
//
// Options:
//   parameter       required: a JSON pointer into the tandem document (as GET /v1/mills/default
//                   shows it, in its names and units) that names a number or a list of numbers:
//                   "/speed_m_per_s", "/spans/length_m/1" (one span), "/spans/tension_MPa"
//                   (every span's set point at once), "/exit_thickness_mm/4" (the schedule),
//                   "/stands/2/lubricant/viscosity_Pa_s" (one stand's field; the stands are
//                   0-based as in any JSON pointer)
//   values | range  as a stand's sweep (api/sweep_json.h), at most max_tandem_sweep_points
//   quantity        "critical_speed" (default: the three critical speeds and the headline) |
//                   "stability" (at the mill's speed: the rightmost root, rho, the root count)
//   critical_speed  the search options over mill speeds (quantity critical_speed only)
//
// Every value is written into the request's resolved tandem document and read back through the
// mill's own validation (field bounds, the schedule falling, the per-stand rules), so a value the
// mill cannot have is a problem at /options/values/<i> (or /options/range/...) naming the field,
// its bound and unit.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "api/field_errors.h"
#include "api/result_table.h"
#include "api/tandem_points.h"
#include "api/units.h"
#include "core/mill/mill.h"
#include "core/stability.h"

namespace rollgap::api {

// A point may take seconds (five stands' critical speeds): fewer points than a stand's sweep.
inline constexpr int max_tandem_sweep_points = 200;

struct TandemSweepPlan {
    std::string parameter;  // the pointer into the tandem document
    Unit unit = units::one;
    std::vector<double> values;       // in the field's unit, as the client wrote them
    std::vector<core::Mill> mills;    // one per value; filled only for a valid request
    TandemPointSpec spec;             // what each point holds
    nlohmann::json resolved_options;  // the echo
};

// `valid_mill` is the request's mill if it passed validation, else nullptr (then the values are
// not checked against it and no mills are built).
TandemSweepPlan tandem_sweep_plan_from_json(const nlohmann::json& options,
                                            const std::string& pointer,
                                            const core::Mill* valid_mill, FieldErrors& errors);

// The points' documents (one per mill of plan.mills[first + i]) computed now: what a chunk of a
// job writes. Cancellation is polled between points.
nlohmann::json tandem_sweep_points_json(const TandemSweepPlan& plan, std::size_t first,
                                        std::size_t count, const core::Control& control);

// The result from all points' documents in order.
nlohmann::json tandem_sweep_result_json(const TandemSweepPlan& plan, nlohmann::json points);

std::vector<ResultSchema> tandem_sweep_result_schemas();
std::span<const CsvTable> tandem_sweep_csv_tables();

}  // namespace rollgap::api
