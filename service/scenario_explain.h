#pragma once
// `rollgap scenario --explain`: the field glossary of the scenario, one entry per row of the
// api scenario field table (pointer, unit, bounds, default, description), as plain text, and
// of the tandem mill's field table after it.

#include <string>

namespace rollgap::service {

// the scenario's fields, then the tandem document's, then their plant units
std::string scenario_explanation();

// The tandem document's fields (api/tandem_schema.h) in the same form.
std::string tandem_explanation();

// The keys that give a field in a plant unit (api/plant_units.h), with unit and conversion.
std::string plant_unit_explanation();

}  // namespace rollgap::service
