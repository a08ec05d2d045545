#pragma once
// A small self-contained SVG line-plot writer for the paper reproduction (tools/reproduce_paper):
// axes with ticks and labelled units, a legend, one polyline per series, and markers for points
// that have no value (drawn on the top or bottom edge of the plot area, e.g. "stable up to the
// end of the search range" or "unstable at the lower bound"). No dependencies beyond the
// standard library; the output is deterministic for the same input.

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace rollgap::tools {

enum class Marker { none, circle, square, diamond, triangle_up, triangle_down, cross };

struct Series {
    std::string label;
    std::vector<double> x, y;  // a non-finite y breaks the line and draws no marker
    std::string color;         // CSS colour; empty: the next palette colour
    bool line = true;
    std::string dash;  // SVG stroke-dasharray, empty: solid
    double line_width = 2.0;
    Marker marker = Marker::circle;
    bool hollow = false;
    double marker_size = 4.0;
};

// Points without a value: drawn on an edge of the plot area at their x.
struct EdgeMarkers {
    enum class Edge { bottom, top };
    std::string label;
    std::vector<double> x;
    Edge edge = Edge::bottom;
    Marker marker = Marker::triangle_down;
    std::string color = "#555555";
};

struct VerticalLine {
    double x;
    std::string label;
    std::string color = "#888888";
};

struct Plot {
    std::string title;
    std::string x_label;  // with the unit, e.g. "η0 (mPa·s)"
    std::string y_label;
    bool log_y = false;
    // Axis ranges; NaN: from the data (with nice rounding).
    double x_min = std::numeric_limits<double>::quiet_NaN(),
           x_max = std::numeric_limits<double>::quiet_NaN();
    double y_min = std::numeric_limits<double>::quiet_NaN(),
           y_max = std::numeric_limits<double>::quiet_NaN();
    std::vector<Series> series;
    std::vector<EdgeMarkers> edges;
    std::vector<VerticalLine> vertical_lines;
    std::vector<std::string> notes;  // lines of text under the plot
    int width = 900;
    int height = 500;
};

std::string render_svg(const Plot& plot);

// Writes render_svg(plot) to `path`; false on an I/O error.
bool write_svg(const std::filesystem::path& path, const Plot& plot);

}  // namespace rollgap::tools
