#pragma once
// The mill under its stands' calibration posteriors (docs/model.md §13.7): reading
// tandem_speed_limit's options.posteriors and writing the result's `uncertainty`.
//
//   posteriors   [posterior | null, ...]: one per stand, as calibrate returns it for that stand
//                (its fields the stand's own scenario fields, its values the stand's, none a field
//                the mill gives the stand); the stands independent, so the mill's covariance is
//                block-diagonal.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/posterior_json.h"
#include "api/result_table.h"
#include "core/mill/mill_speed_limit.h"

namespace rollgap::api {

// "must be an array of one <item> per stand (<n> here)<what>": the check every per-stand list
// shares (at most core::max_mill_stands items; exactly the mill's count when it is known, stands
// > 0). Reports at `pointer` and returns whether `list` is an array at all (its items are then
// read even when the count is wrong: every violation at once).
bool check_per_stand_list(const nlohmann::json& list, const std::string& pointer, int stands,
                          std::string_view item, std::string_view what, FieldErrors& errors);

struct MillPosteriors {
    std::vector<std::optional<Posterior>> stands;  // one per stand, nullopt: known exactly
    core::MillPosterior mill;                      // the numbers and Σ, block-diagonal
};

// `list` (not null) at `pointer`; `mill`: the request's valid mill or nullptr (then the values
// and the count are not checked against it). nullopt when anything was refused.
std::optional<MillPosteriors> read_mill_posteriors(const nlohmann::json& list,
                                                   const std::string& pointer,
                                                   const core::Mill* mill, FieldErrors& errors);

// The result's `uncertainty` (TandemCriticalSpeedUncertainty): `critical` and `uncertainty` of
// one answer, at `confidence`, with the posteriors it was propagated from.
nlohmann::json mill_uncertainty_json(const core::MillCriticalSpeeds& critical,
                                     const core::MillSpeedUncertainty& uncertainty,
                                     double confidence,
                                     const std::vector<std::optional<Posterior>>& posteriors);
std::vector<ResultSchema> mill_uncertainty_schemas();

}  // namespace rollgap::api
