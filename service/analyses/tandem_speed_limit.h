#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "service/analyses/analysis.h"

namespace rollgap::service {

// The analysis "tandem_speed_limit" (docs/model.md §13.5): the mill speeds a tandem mill may
// run at under the plant's limits, mill-wide or per stand, and the chatter limit.
PreparedAnalysis prepare_tandem_speed_limit(const core::Mill& mill, const nlohmann::json& options,
                                            const std::string& options_pointer,
                                            api::FieldErrors& errors);

}  // namespace rollgap::service
