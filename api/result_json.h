#pragma once
// Roll-bite result → JSON, engineering units in every name. Skidding, contact lost and
// solver failure are results with a status (the question had an answer: "no steady bite"),
// not errors of the request.

#include <nlohmann/json.hpp>

#include <vector>

#include "api/result_table.h"
#include "core/roll_bite.h"

namespace rollgap::api {

// {"status", "message", "force_kN", ..., "skidding": {...}, "distribution": {"x_mm": [...], ...}}
// The distribution is columnar (one array per quantity, equal lengths): compact, and what
// plotting code wants. Every member is always present; a quantity the solve did not produce
// is null: with skidding everything but the bite geometry (contact length, inlet angle); with
// contact_lost everything but force and torque, which are 0; with solver_failure everything.
// Non-finite values are null as well.
nlohmann::json bite_result_json(const core::BiteResult& result);

// The tables that write it (result_table.h): components RollGapResult, Skidding, BiteDistribution.
const ResultTable<core::BiteResult>& bite_result_table();
const ResultTable<core::BiteResult>& skidding_table();
const ResultTable<std::vector<core::BitePoint>>& bite_distribution_table();
std::vector<ResultSchema> bite_result_schemas();

}  // namespace rollgap::api
