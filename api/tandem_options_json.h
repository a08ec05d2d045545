#pragma once
// Options of the analysis "tandem" (component TandemOptions): the critical-speed search over mill
// speeds, critical_speed and detail as the stability analysis reads them, and the time domain
// (docs/model.md §12.9):
//   time_series          false  whether to integrate the mill in time
//   window_s             0.5    (0, 5] s simulated
//   time_series_points   400    [2, 20000] most points kept per stand, and at most
//                               max_mill_time_series_values over all stands
//   kick_um              0.1    [0, 100] um, the gap kick at t = 0
//   kick_stand           0      [0, 6], at most the stand count; 0: the rightmost root's moving
//                               stand (the last stand without one)

#include <string>

#include <nlohmann/json.hpp>

#include "api/field_errors.h"
#include "api/stability_json.h"

namespace rollgap::api {

// The points of a mill's time series over all its stands (the answer's size): 20,000, as one
// stand's series may hold.
inline constexpr int max_mill_time_series_values = 20000;

struct TandemOptions {
    StabilityOptions stability;
    bool time_series = false;
    double window = 0.5;  // s
    int time_series_points = 400;
    double kick = 0.1e-6;  // m
    int kick_stand = 0;    // 1-based; 0: the moving stand of the rightmost root
};

// `stands`: the mill's stand count, which bounds kick_stand.
TandemOptions tandem_options_from_json(const nlohmann::json& options, const std::string& pointer,
                                       int stands, FieldErrors& errors);
nlohmann::json tandem_options_json(const TandemOptions& options);

}  // namespace rollgap::api
