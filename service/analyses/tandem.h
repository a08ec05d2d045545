#pragma once
// Analysis "tandem": a tandem mill at its speed (docs/model.md §12): the pass schedule, the
// frozen modes, the regenerative margin, the nominal-delay root count and the rightmost root by
// stand, and the mill's three critical speeds with the headline (options.critical_speed).

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_tandem(const core::Mill& mill, const nlohmann::json& options,
                                const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
