#pragma once
// `rollgap scenario --explain`: the field glossary of the scenario, one entry per row of the
// api scenario field table (pointer, unit, bounds, default, description), as plain text, and
// of the tandem mill's field table after it.

#include <string>

namespace rollgap::service {

std::string scenario_explanation();  // the scenario's fields, then the tandem document's

// The tandem document's fields (api/tandem_schema.h) in the same form.
std::string tandem_explanation();

}  // namespace rollgap::service
