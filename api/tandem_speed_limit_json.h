#pragma once
// Options and result of the analysis "tandem_speed_limit" (docs/model.md §13.5): the speeds a
// tandem mill may run at under a plant's limits, the limit that binds and its stand, the margins
// at the mill speed. Stands are numbered from 1 in results, as in every mill result.
//
// Options (units in the names; a limit that is absent is not checked):
//   max_roll_force_kN, max_torque_kN_m, max_power_kW, min_forward_slip: as speed_limit's, for
//                       every stand
//   stands              [{max_roll_force_kN, ...}, ...]: one object per stand from the entry, each
//                       member replacing the mill-wide value for that stand ({} keeps them)
//   chatter, chatter_margin: the chatter limit is the mill's headline critical speed x (1 -
//                       margin)
//   speed_min_m_per_s … relative_tolerance: the mill-speed range and the critical-speed search
//   posteriors          [posterior | null, ...]: one per stand, as calibrate returns it for that
//                       stand (its fields the stand's own scenario fields, its values the
//                       stand's); the stands independent (docs/model.md §13.7)
//   confidence          0.95  of the one-sided bounds the limits are taken at under posteriors
//   samples, seed       0, 1  with posteriors: the headline critical speed at this many seeded
//                       draws too (each draw's mill searched whole), the check on sigma
//   what_to_change      true  the advised mill speed's derivatives at the binding limit
//   changes             [{field, step}]: tandem-document pointers and their typical steps
//                       (api/tandem_change_json.h; default: default_mill_change_fields)

#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "api/field_errors.h"
#include "api/posterior_json.h"
#include "api/result_table.h"
#include "api/tandem_change_json.h"
#include "core/mill/mill_speed_limit.h"
#include "core/stability.h"

namespace rollgap::api {

struct TandemSpeedLimitOptions {
    core::PlantLimits mill_wide;        // the values for every stand (chatter members unused)
    core::MillPlantLimits limits;       // resolved: one per stand, chatter and margin
    core::CriticalSpeedOptions search;  // the mill-speed range and the critical-speed search
    bool what_to_change = true;
    std::vector<MillChangeField> changes;  // the request's, or the defaults for its stand count
    // one per stand when given (limits.posterior assembled from them), else empty
    std::vector<std::optional<Posterior>> posteriors;
};

// `valid_mill`: the request's mill if it was read without violations, else nullptr (the lists'
// lengths and the posteriors' values are then not checked against it).
TandemSpeedLimitOptions tandem_speed_limit_options_from_json(const nlohmann::json& options,
                                                             const std::string& pointer,
                                                             const core::Mill* valid_mill,
                                                             FieldErrors& errors);
// The options as applied: the mill-wide values as given, `stands` resolved (every stand's own).
nlohmann::json tandem_speed_limit_options_json(const TandemSpeedLimitOptions& options);

struct TandemSpeedLimitReport {
    core::MillPlantLimits limits;
    std::vector<std::optional<Posterior>> posteriors;  // the options', for the uncertainty's rows
    core::MillSpeedLimitResult result;
    std::optional<MillWhatToChange> what_to_change;
};

nlohmann::json tandem_speed_limit_result_json(const TandemSpeedLimitReport& report);
std::vector<ResultSchema> tandem_speed_limit_result_schemas();
std::span<const CsvTable> tandem_speed_limit_csv_tables();

// "The mill runs at 15.00 m/s, 104 % of its 14.36 m/s chatter limit (stand 5 moves); ..."
std::string tandem_speed_limit_summary(const TandemSpeedLimitReport& report);

}  // namespace rollgap::api
