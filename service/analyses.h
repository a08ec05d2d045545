#pragma once
// The analyses the service offers. Adding one is one row in analyses.cpp.

#include <span>
#include <string_view>

#include "service/analysis.h"

namespace rollgap::service {

std::span<const Analysis> analyses();
// The row named `name` in `table`, or nullptr.
const Analysis* find_analysis(std::span<const Analysis> table, std::string_view name);

}  // namespace rollgap::service
