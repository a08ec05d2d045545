#pragma once
// The analyses the service offers: the rows of table.cpp (what adding one takes: analysis.h).

#include <span>
#include <string_view>

#include "api/problem.h"
#include "service/analyses/analysis.h"

namespace rollgap::service {

std::span<const Analysis> analyses();
// The row named `name` in `table`, or nullptr.
const Analysis* find_analysis(std::span<const Analysis> table, std::string_view name);
// The problem `unknown_analysis` for `name`, listing the analyses of `table`.
api::Problem unknown_analysis_problem(std::span<const Analysis> table, std::string_view name);

}  // namespace rollgap::service
