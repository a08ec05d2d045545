#pragma once
// Analysis "tandem_map": a mill's critical speeds or its stability at its speed over a grid of
// two numbers of its document (docs/model.md §12.10); pointwise, so a job splits its cells into
// chunks that any replica computes.

#include "service/analyses/analysis.h"

namespace rollgap::service {

PreparedAnalysis prepare_tandem_map(const core::Mill& mill, const nlohmann::json& options,
                                    const std::string& options_pointer, api::FieldErrors& errors);

}  // namespace rollgap::service
