#pragma once
// Analysis "tandem_sweep": one value of a mill's document (a per-stand field, a span length, a
// tension set point, the schedule, the mill speed) over a list or a range, the mill's critical
// speeds or its stability at its speed at each (docs/model.md §12.10); pointwise, so a job splits
// its values into chunks that any replica computes.

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_tandem_sweep(const core::Mill& mill, const nlohmann::json& options,
                                      const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
