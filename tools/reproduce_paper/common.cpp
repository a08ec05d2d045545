#include "tools/reproduce_paper/common.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace rollgap::tools::paper {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

namespace {

std::mutex log_mutex;

}  // namespace

void log(const std::string& message) {
    std::lock_guard<std::mutex> lock(log_mutex);
    std::fprintf(stderr, "reproduce_paper: %s\n", message.c_str());
    std::fflush(stderr);
}

std::string fmt(double v, int decimals) {
    if (!std::isfinite(v)) return "–";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
    std::string s = buffer;
    if (s.rfind("-0", 0) == 0 && std::strtod(s.c_str(), nullptr) == 0.0) s.erase(0, 1);
    return s;
}

std::string fmtg(double v, int significant) {
    if (!std::isfinite(v)) return "–";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", significant, v);
    return buffer;
}

std::string csv_number(double v) {
    if (!std::isfinite(v)) return "";
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.10g", v);
    return buffer;
}

std::string percent(double fraction, int decimals) {
    return (fraction >= 0 ? "+" : "−") + fmt(std::abs(fraction) * 100.0, decimals) + " %";
}

const char* film_name(InletFilmModel m) {
    return m == InletFilmModel::paper ? "paper" : "eulerian";
}

std::string variant_suffix(double asperity_factor) {
    return asperity_factor == 1.0 ? "" : "_ma" + fmt(asperity_factor, 1);
}

std::string variant_title(double asperity_factor) {
    return asperity_factor == 1.0
               ? ""
               : " (boundary-friction variant m_a = " + fmt(asperity_factor, 1) + ")";
}

}  // namespace rollgap::tools::paper
