#pragma once
// What every part of the paper reproduction shares: the names it uses from core and tools,
// numbers as the report and its CSV files print them, progress on stderr, and the two inlet film
// models every figure is run with.

#include <chrono>
#include <limits>
#include <string>

#include "core/scenario.h"
#include "core/stability.h"
#include "tools/diagnostics.h"
#include "tools/svg_plot.h"

namespace rollgap::tools::paper {

using core::CriticalSpeedStatus;
using core::InletFilmModel;
using core::Scenario;
using tools::EdgeMarkers;
using tools::Marker;
using tools::ModeDiagnostics;
using tools::Plot;
using tools::Series;

// A value that does not exist for a point (no critical speed, ...): "–" in tables, empty in CSV.
inline constexpr double no_value = std::numeric_limits<double>::quiet_NaN();
inline constexpr InletFilmModel film_models[] = {InletFilmModel::paper, InletFilmModel::eulerian};

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0);

// One progress line on stderr; safe from several threads.
void log(const std::string& message);

// Fixed decimals; "–" for a value that does not exist; no "-0".
std::string fmt(double v, int decimals);
// Significant digits ("%g").
std::string fmtg(double v, int significant = 3);
// A CSV cell: 10 significant digits, empty for a value that does not exist.
std::string csv_number(double v);
// "+12.3 %" / "−4.5 %" of a relative change.
std::string percent(double fraction, int decimals = 1);
const char* film_name(InletFilmModel m);
// The file-name suffix of a boundary-friction variant: "" for the paper's m_a = 1, "_ma0.7" else.
std::string variant_suffix(double asperity_factor);
// "" for m_a = 1, " (boundary-friction variant m_a = 0.7)" else: appended to plot titles.
std::string variant_title(double asperity_factor);

}  // namespace rollgap::tools::paper
