#pragma once
// Options and result of the all-in-one analysis "evaluate" (what the HTTP service answers by
// default): the roll gap at the scenario's speed, the stability there, the critical speed and
// the vibration amplitude at the scenario's speed.
//
// Options: {"critical_speed": {search options, stability_json.h},
//           "amplitude": {run options without speeds_m_per_s, amplitude_json.h},
//           "detail": "full" | "summary" (stability_json.h)}

#include <string>

#include <nlohmann/json.hpp>

#include "api/amplitude_json.h"
#include "api/field_errors.h"
#include "api/result_table.h"
#include "api/stability_json.h"
#include "core/evaluation.h"

namespace rollgap::api {

struct EvaluationOptions {
    core::CriticalSpeedOptions critical_speed;
    core::AmplitudeOptions amplitude;
    Detail detail = Detail::full;
};

EvaluationOptions evaluation_options_from_json(const nlohmann::json& options,
                                               const std::string& pointer, FieldErrors& errors);
nlohmann::json evaluation_options_json(const EvaluationOptions& options);

// {"roll_gap": <the roll_gap result>, "stability": <speed_stability_summary_json>,
//  "critical_speed": <critical_speed_summary_json>, "amplitude": <amplitude_result_json>}.
// Without a steady bite at the scenario's speed (roll_gap status not "ok") nothing vibrates
// about it: the other three then have status "no_steady_state" and null figures (core stops at
// the roll gap then; `scenario_speed`, m/s, fills in the speed it did not record).
nlohmann::json evaluation_result_json(const core::Evaluation& evaluation,
                                      const EvaluationOptions& options, double scenario_speed);

// Its OpenAPI component (EvaluateResult), from the table that writes it.
std::vector<ResultSchema> evaluation_result_schemas();

}  // namespace rollgap::api
