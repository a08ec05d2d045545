#pragma once
// Analysis "speed_limit": the speeds a stand may run at under a plant's limits (roll force,
// torque, power, skid margin, chatter with a safety margin), the limit that binds and the
// margins at the operating speed; with a calibration posterior, the critical speed's uncertainty
// carried to the chatter limit (docs/model.md §13).

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_speed_limit(const core::Scenario& scenario, const nlohmann::json& options,
                                     const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
