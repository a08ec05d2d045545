#pragma once
// Options and result of the analysis "speed_limit" (docs/model.md §13): the speeds a stand may
// run at under a plant's limits, the limit that binds, the margins at the operating speed, and
// the critical speed's uncertainty from a calibration posterior carried to the chatter limit.
//
// Options (units in the names; a limit that is absent is not checked):
//   max_roll_force_kN   (0, 1e6]     the roll force may not exceed it
//   max_torque_kN_m     (0, 1e5]     per work roll
//   max_power_kW        (0, 1e6]     both work rolls
//   min_forward_slip    [-0.5, 0.5]  the skid margin: the forward slip may not fall below it
//   chatter             true         whether the critical speed is a limit
//   chatter_margin      0     [0, 1) the chatter limit is (V_c - z sigma)(1 - margin)
//   confidence          0.95  [0.5, 1) of the one-sided lower bound on V_c
//   speed_min_m_per_s … relative_tolerance: the speed range and the critical-speed search
//   posterior           {parameters: [{field, value, standard_error}], correlation}: as
//                       calibrate returns it (its other members are ignored); the values must
//                       be the scenario's (send calibrated_scenario as the scenario)
//   samples             0     [0, 500] seeded draws from the posterior, the check on the linear
//                       propagation; 0: none
//   seed                1     of the draws
//   what_to_change      true  the advised speed's derivatives at the binding limit
//   changes             [{field, step}]: the fields differentiated and their typical steps, in
//                       the fields' units (default: default_change_fields())

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/posterior_json.h"
#include "api/result_table.h"
#include "api/scenario_schema.h"
#include "core/limit_sensitivity.h"
#include "core/propagation.h"
#include "core/scenario.h"
#include "core/speed_limit.h"
#include "core/stability.h"

namespace rollgap::api {

inline constexpr int max_change_fields = 30;

// A field a plant can set and its typical step (SI): what "what to change" differentiates.
struct ChangeField {
    const ScenarioField* field = nullptr;
    double step = 0.0;
};
// The default list: the tensions, the reduction, the viscosity, the roughnesses, the roll radius.
std::vector<ChangeField> default_change_fields();
inline constexpr int max_posterior_samples = 500;

struct SpeedLimitOptions {
    core::PlantLimits limits;
    core::CriticalSpeedOptions search;  // the speed range of every limit and the chatter search
    std::optional<Posterior> posterior;
    int samples = 0;
    int seed = 1;
    bool what_to_change = true;
    std::vector<ChangeField> changes = default_change_fields();
};

// `valid_scenario`: the request's scenario if it passed validation (the posterior's values are
// checked against it), else nullptr.
SpeedLimitOptions speed_limit_options_from_json(const nlohmann::json& options,
                                                const std::string& pointer,
                                                const core::Scenario* valid_scenario,
                                                FieldErrors& errors);
nlohmann::json speed_limit_options_json(const SpeedLimitOptions& options);

// The critical speed's uncertainty from the posterior (docs/model.md §13.2).
struct SpeedLimitUncertainty {
    const Posterior* posterior = nullptr;
    double confidence = 0.95;
    core::Propagated linear;
    std::optional<core::Propagated> sampled;
    int seed = 1;
};

// What to change (docs/model.md §13.4): the binding limit's derivatives, one per change field.
struct WhatToChange {
    std::vector<ChangeField> changes;
    core::BindingSensitivity sensitivity;
    core::Scenario scenario;  // the values the changes start from
};

struct SpeedLimitReport {
    core::PlantLimits limits;
    core::SpeedLimitResult result;
    std::optional<SpeedLimitUncertainty> uncertainty;
    std::optional<WhatToChange> what_to_change;
};

nlohmann::json speed_limit_result_json(const SpeedLimitReport& report);
std::vector<ResultSchema> speed_limit_result_schemas();
// The members of a checked limit (the CSV columns).
std::vector<std::string> speed_limit_check_columns();
// The members of a checked limit's row (component SpeedLimitCheck), for the mill's rows that
// add the stand (api/tandem_speed_limit_json.h).
std::vector<Member<core::LimitAnswer>> speed_limit_check_members();

// The figures of the summaries, for people: "62 %", "24.00 m/s" (the mill's too).
std::string summary_percent_text(double fraction);
std::string summary_speed_text(double speed);

// A limit's kind as the results name it (null for none), and its schema.
nlohmann::json speed_limit_kind_json(const std::optional<core::SpeedLimitKind>& kind);
nlohmann::json speed_limit_kind_schema(bool nullable);
// The draws' figures (SampledCriticalSpeed), for the mill's uncertainty too.
nlohmann::json sampled_critical_speed_json(const core::Propagated& sampled);

// One sentence for people: "runs at 15 m/s, 83 % of its 18.09 m/s chatter limit; ...".
std::string speed_limit_summary(const SpeedLimitReport& report);

}  // namespace rollgap::api
