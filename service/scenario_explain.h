#pragma once
// `rollgap scenario --explain`: the field glossary of the scenario, one entry per row of the
// api scenario field table (pointer, unit, bounds, default, description), as plain text.

#include <string>

namespace rollgap::service {

std::string scenario_explanation();

}  // namespace rollgap::service
