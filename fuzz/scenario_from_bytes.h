#pragma once
// A valid scenario from arbitrary bytes: each row of the API's field table (api/scenario_schema.h)
// takes its value from the input, inside the row's own range, and the API's cross-field rules
// (api/scenario_consistency.h) decide whether the result is a scenario a client could send. The
// core harnesses therefore only ever see what the product can hand to core.

#include <optional>

#include "core/scenario.h"
#include "fuzz/fuzz_input.h"

namespace rollgap::fuzz {

// Per field one selector byte: keep the default (most inputs, so the fuzzer can vary a few
// fields at a time around a working scenario), the range's lower or upper end (corners, with
// open ends nudged inside), or a value drawn from two more bytes. Null when the cross-field
// rules refuse the scenario.
std::optional<core::Scenario> scenario_from_bytes(FuzzInput& input);

}  // namespace rollgap::fuzz
