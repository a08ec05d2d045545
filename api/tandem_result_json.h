#pragma once
// The result of the analysis "tandem" (docs/model.md §12.8): the mill's steady state (the pass
// schedule, per stand), its stability at the mill speed (the frozen modes, the regenerative
// margin, the nominal-delay root count and the rightmost root described by stand) and, when
// asked, the three critical speeds with the headline. Stands are numbered from 1 in results,
// as a plant numbers them (the request's /tandem/stands/0 is stand 1).

#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "api/csv.h"
#include "api/result_table.h"
#include "api/stability_json.h"
#include "core/mill/mill.h"
#include "core/mill/mill_critical_speed.h"
#include "core/mill/mill_stability.h"
#include "core/mill/mill_time.h"

namespace rollgap::api {

struct TandemReport {
    core::Mill mill;
    core::MillSpeedStability at_speed;
    core::MillRootDescription rightmost;
    std::optional<core::MillCriticalSpeeds> critical;
    Detail detail = Detail::full;
    // the time domain (options.time_series): the run, the stand kicked (0-based) and the kick, m
    std::optional<core::MillTimeResult> time;
    int kicked_stand = -1;
    double kick = 0.0;
};

nlohmann::json tandem_result_json(const TandemReport& report);
std::vector<ResultSchema> tandem_result_schemas();
std::span<const CsvTable> tandem_csv_tables();

// The three critical speeds and the headline (component TandemCriticalSpeeds), for other mill
// results that carry them (the mill's speed limit).
nlohmann::json tandem_critical_speeds_json(const core::MillCriticalSpeeds& speeds);

// A stand number as mill results give it (1-based, as a plant numbers its stands), null for
// "none" (index -1), and its schema.
nlohmann::json stand_number(int index);
nlohmann::json stand_number_schema(bool nullable);

}  // namespace rollgap::api
