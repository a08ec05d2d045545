#include "tools/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace rollgap::tools {

namespace {

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                "#9467bd", "#8c564b", "#17becf", "#7f7f7f"};

std::string escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string num(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.2f", v);
    return buffer;
}

double nice_step(double range, int target) {
    const double raw = range / std::max(1, target);
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / magnitude;
    const double nice = f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0;
    return nice * magnitude;
}

std::string tick_label(double value, double step) {
    int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
    if (std::abs(value) < 0.5 * step) value = 0.0;  // no "-0"
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
    return buffer;
}

std::string log_tick_label(double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%g", value);
    return buffer;
}

// A UTF-8 aware character count (for the legend's width estimate and wrapping).
std::size_t glyphs(const std::string& s) {
    std::size_t n = 0;
    for (unsigned char c : s) {
        if ((c & 0xC0) != 0x80) ++n;
    }
    return n;
}

std::vector<std::string> wrap(const std::string& text, std::size_t width) {
    std::vector<std::string> lines;
    std::istringstream words(text);
    std::string word, line;
    while (words >> word) {
        if (!line.empty() && glyphs(line) + 1 + glyphs(word) > width) {
            lines.push_back(line);
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) lines.push_back(line);
    if (lines.empty()) lines.push_back("");
    return lines;
}

void draw_marker(std::ostringstream& out, Marker marker, double x, double y, double size,
                 const std::string& color, bool hollow) {
    const std::string fill = hollow ? "#ffffff" : color;
    const std::string style = "fill=\"" + fill + "\" stroke=\"" + color + "\" stroke-width=\"1.5\"";
    const double s = size;
    switch (marker) {
        case Marker::none: return;
        case Marker::circle:
            out << "<circle cx=\"" << num(x) << "\" cy=\"" << num(y) << "\" r=\"" << num(s) << "\" "
                << style << "/>\n";
            return;
        case Marker::square:
            out << "<rect x=\"" << num(x - s) << "\" y=\"" << num(y - s) << "\" width=\""
                << num(2 * s) << "\" height=\"" << num(2 * s) << "\" " << style << "/>\n";
            return;
        case Marker::diamond:
            out << "<polygon points=\"" << num(x) << "," << num(y - 1.3 * s) << " "
                << num(x + 1.3 * s) << "," << num(y) << " " << num(x) << "," << num(y + 1.3 * s)
                << " " << num(x - 1.3 * s) << "," << num(y) << "\" " << style << "/>\n";
            return;
        case Marker::triangle_up:
            out << "<polygon points=\"" << num(x) << "," << num(y - 1.3 * s) << " "
                << num(x + 1.2 * s) << "," << num(y + 0.9 * s) << " " << num(x - 1.2 * s) << ","
                << num(y + 0.9 * s) << "\" " << style << "/>\n";
            return;
        case Marker::triangle_down:
            out << "<polygon points=\"" << num(x) << "," << num(y + 1.3 * s) << " "
                << num(x + 1.2 * s) << "," << num(y - 0.9 * s) << " " << num(x - 1.2 * s) << ","
                << num(y - 0.9 * s) << "\" " << style << "/>\n";
            return;
        case Marker::cross:
            out << "<path d=\"M" << num(x - s) << "," << num(y - s) << " L" << num(x + s) << ","
                << num(y + s) << " M" << num(x - s) << "," << num(y + s) << " L" << num(x + s)
                << "," << num(y - s) << "\" stroke=\"" << color
                << "\" stroke-width=\"2\" fill=\"none\"/>\n";
            return;
    }
}

struct Axis {
    double lo = 0.0, hi = 1.0;
    bool log = false;
    std::vector<double> major, minor;
    double step = 1.0;  // linear axes: the major tick step
};

Axis make_linear_axis(double lo, double hi, bool lo_fixed, bool hi_fixed) {
    Axis axis;
    if (!(hi > lo)) {
        const double pad = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
        lo -= pad;
        hi += pad;
    }
    axis.step = nice_step(hi - lo, 6);
    axis.lo = lo_fixed ? lo : std::floor(lo / axis.step + 1e-9) * axis.step;
    axis.hi = hi_fixed ? hi : std::ceil(hi / axis.step - 1e-9) * axis.step;
    axis.step = nice_step(axis.hi - axis.lo, 6);
    for (double t = std::ceil(axis.lo / axis.step - 1e-9) * axis.step;
         t <= axis.hi + 1e-9 * axis.step; t += axis.step) {
        axis.major.push_back(t);
    }
    return axis;
}

Axis make_log_axis(double lo, double hi, bool lo_fixed, bool hi_fixed) {
    Axis axis;
    axis.log = true;
    if (!(lo > 0.0)) lo = hi > 0.0 ? hi / 10.0 : 1.0;
    if (!(hi > lo)) hi = lo * 10.0;
    axis.lo = lo_fixed ? lo : std::pow(10.0, std::floor(std::log10(lo) + 1e-9));
    axis.hi = hi_fixed ? hi : std::pow(10.0, std::ceil(std::log10(hi) - 1e-9));
    const int first = static_cast<int>(std::floor(std::log10(axis.lo) + 1e-9));
    const int last = static_cast<int>(std::ceil(std::log10(axis.hi) - 1e-9));
    for (int e = first; e <= last; ++e) {
        const double decade = std::pow(10.0, e);
        if (decade >= axis.lo * (1 - 1e-9) && decade <= axis.hi * (1 + 1e-9))
            axis.major.push_back(decade);
        for (int m = 2; m <= 9; ++m) {
            const double t = m * decade;
            if (t > axis.lo && t < axis.hi) axis.minor.push_back(t);
        }
    }
    return axis;
}

}  // namespace

std::string render_svg(const Plot& plot) {
    // Data ranges
    double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
    for (const Series& s : plot.series) {
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (!std::isfinite(s.x[i])) continue;
            x_lo = std::min(x_lo, s.x[i]);
            x_hi = std::max(x_hi, s.x[i]);
            if (!std::isfinite(s.y[i]) || (plot.log_y && s.y[i] <= 0.0)) continue;
            y_lo = std::min(y_lo, s.y[i]);
            y_hi = std::max(y_hi, s.y[i]);
        }
    }
    for (const EdgeMarkers& e : plot.edges) {
        for (double x : e.x) {
            x_lo = std::min(x_lo, x);
            x_hi = std::max(x_hi, x);
        }
    }
    if (!std::isfinite(x_lo)) {
        x_lo = 0.0;
        x_hi = 1.0;
    }
    if (!std::isfinite(y_lo)) {
        y_lo = plot.log_y ? 1.0 : 0.0;
        y_hi = plot.log_y ? 10.0 : 1.0;
    }
    const bool x_lo_fixed = std::isfinite(plot.x_min), x_hi_fixed = std::isfinite(plot.x_max);
    const bool y_lo_fixed = std::isfinite(plot.y_min), y_hi_fixed = std::isfinite(plot.y_max);
    if (x_lo_fixed) x_lo = plot.x_min;
    if (x_hi_fixed) x_hi = plot.x_max;
    if (y_lo_fixed) y_lo = plot.y_min;
    if (y_hi_fixed) y_hi = plot.y_max;
    const Axis xa = make_linear_axis(x_lo, x_hi, x_lo_fixed, x_hi_fixed);
    const Axis ya = plot.log_y ? make_log_axis(y_lo, y_hi, y_lo_fixed, y_hi_fixed)
                               : make_linear_axis(y_lo, y_hi, y_lo_fixed, y_hi_fixed);

    // Layout
    const double legend_width = 290.0;
    const double left = 84.0, top = 48.0;
    const double right = plot.width - legend_width;
    const double bottom = plot.height - 62.0;
    std::vector<std::vector<std::string>> note_lines;
    int note_count = 0;
    for (const std::string& note : plot.notes) {
        note_lines.push_back(wrap(note, 130));
        note_count += static_cast<int>(note_lines.back().size());
    }
    const double total_height = plot.height + 17.0 * note_count + (note_count ? 6.0 : 0.0);

    auto px = [&](double x) { return left + (x - xa.lo) / (xa.hi - xa.lo) * (right - left); };
    auto py = [&](double y) {
        if (ya.log)
            return bottom - (std::log10(y) - std::log10(ya.lo)) /
                                (std::log10(ya.hi) - std::log10(ya.lo)) * (bottom - top);
        return bottom - (y - ya.lo) / (ya.hi - ya.lo) * (bottom - top);
    };

    std::ostringstream out;
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << plot.width << "\" height=\""
        << num(total_height) << "\" viewBox=\"0 0 " << plot.width << " " << num(total_height)
        << "\" font-family=\"DejaVu Sans, Arial, sans-serif\">\n";
    out << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
    out << "<defs><clipPath id=\"plot-area\"><rect x=\"" << num(left) << "\" y=\"" << num(top - 1)
        << "\" width=\"" << num(right - left) << "\" height=\"" << num(bottom - top + 2)
        << "\"/></clipPath></defs>\n";
    out << "<text x=\"" << num(0.5 * (left + right))
        << "\" y=\"26\" text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\">"
        << escape(plot.title) << "</text>\n";

    // Grid and ticks
    out << "<g stroke=\"#e4e4e4\" stroke-width=\"1\">\n";
    for (double t : xa.major)
        out << "<line x1=\"" << num(px(t)) << "\" y1=\"" << num(top) << "\" x2=\"" << num(px(t))
            << "\" y2=\"" << num(bottom) << "\"/>\n";
    for (double t : ya.major)
        out << "<line x1=\"" << num(left) << "\" y1=\"" << num(py(t)) << "\" x2=\"" << num(right)
            << "\" y2=\"" << num(py(t)) << "\"/>\n";
    for (double t : ya.minor)
        out << "<line x1=\"" << num(left) << "\" y1=\"" << num(py(t)) << "\" x2=\"" << num(right)
            << "\" y2=\"" << num(py(t)) << "\" stroke=\"#f2f2f2\"/>\n";
    out << "</g>\n";
    out << "<rect x=\"" << num(left) << "\" y=\"" << num(top) << "\" width=\"" << num(right - left)
        << "\" height=\"" << num(bottom - top)
        << "\" fill=\"none\" stroke=\"#333333\" stroke-width=\"1\"/>\n";
    out << "<g font-size=\"12\" fill=\"#222222\">\n";
    for (double t : xa.major) {
        out << "<line x1=\"" << num(px(t)) << "\" y1=\"" << num(bottom) << "\" x2=\"" << num(px(t))
            << "\" y2=\"" << num(bottom + 5) << "\" stroke=\"#333333\"/>\n";
        out << "<text x=\"" << num(px(t)) << "\" y=\"" << num(bottom + 19)
            << "\" text-anchor=\"middle\">" << escape(tick_label(t, xa.step)) << "</text>\n";
    }
    for (double t : ya.major) {
        out << "<line x1=\"" << num(left - 5) << "\" y1=\"" << num(py(t)) << "\" x2=\"" << num(left)
            << "\" y2=\"" << num(py(t)) << "\" stroke=\"#333333\"/>\n";
        out << "<text x=\"" << num(left - 8) << "\" y=\"" << num(py(t) + 4)
            << "\" text-anchor=\"end\">"
            << escape(ya.log ? log_tick_label(t) : tick_label(t, ya.step)) << "</text>\n";
    }
    for (double t : ya.minor) {
        out << "<line x1=\"" << num(left - 3) << "\" y1=\"" << num(py(t)) << "\" x2=\"" << num(left)
            << "\" y2=\"" << num(py(t)) << "\" stroke=\"#333333\"/>\n";
    }
    out << "</g>\n";
    out << "<text x=\"" << num(0.5 * (left + right)) << "\" y=\"" << num(bottom + 42)
        << "\" text-anchor=\"middle\" font-size=\"14\">" << escape(plot.x_label) << "</text>\n";
    out << "<text transform=\"translate(22," << num(0.5 * (top + bottom))
        << ") rotate(-90)\" text-anchor=\"middle\" font-size=\"14\">" << escape(plot.y_label)
        << "</text>\n";

    // Vertical reference lines
    for (const VerticalLine& v : plot.vertical_lines) {
        if (!(v.x >= xa.lo && v.x <= xa.hi)) continue;
        out << "<line x1=\"" << num(px(v.x)) << "\" y1=\"" << num(top) << "\" x2=\"" << num(px(v.x))
            << "\" y2=\"" << num(bottom) << "\" stroke=\"" << v.color
            << "\" stroke-width=\"1.5\" stroke-dasharray=\"2,3\"/>\n";
        // the label goes on the side of the line with room for it (~6.5 px per glyph at 11 px)
        const bool left_side = px(v.x) + 6.0 + 6.5 * glyphs(v.label) > right;
        out << "<text x=\"" << num(left_side ? px(v.x) - 4 : px(v.x) + 4) << "\" y=\""
            << num(top + 14) << "\" font-size=\"11\" fill=\"" << v.color << "\""
            << (left_side ? " text-anchor=\"end\"" : "") << ">" << escape(v.label) << "</text>\n";
    }

    // Series
    std::vector<std::string> colors;
    int next_color = 0;
    for (const Series& s : plot.series) {
        colors.push_back(s.color.empty() ? kPalette[next_color++ % 8] : s.color);
    }
    out << "<g clip-path=\"url(#plot-area)\">\n";
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
        const Series& s = plot.series[k];
        const std::string& color = colors[k];
        if (s.line) {
            std::string points;
            auto flush = [&] {
                if (points.empty()) return;
                out << "<polyline fill=\"none\" stroke=\"" << color << "\" stroke-width=\""
                    << num(s.line_width) << "\"";
                if (!s.dash.empty()) out << " stroke-dasharray=\"" << s.dash << "\"";
                out << " stroke-linejoin=\"round\" points=\"" << points << "\"/>\n";
                points.clear();
            };
            for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
                const bool ok =
                    std::isfinite(s.x[i]) && std::isfinite(s.y[i]) && !(ya.log && s.y[i] <= 0.0);
                if (!ok) {
                    flush();
                    continue;
                }
                points += num(px(s.x[i])) + "," + num(py(s.y[i])) + " ";
            }
            flush();
        }
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i]) || (ya.log && s.y[i] <= 0.0))
                continue;
            draw_marker(out, s.marker, px(s.x[i]), py(s.y[i]), s.marker_size, color, s.hollow);
        }
    }
    out << "</g>\n";
    for (const EdgeMarkers& e : plot.edges) {
        const double y = e.edge == EdgeMarkers::Edge::bottom ? bottom - 9.0 : top + 9.0;
        for (double x : e.x) {
            if (x >= xa.lo && x <= xa.hi) draw_marker(out, e.marker, px(x), y, 5.0, e.color, false);
        }
    }

    // Legend
    double ly = top + 6.0;
    const double lx = right + 18.0;
    out << "<g font-size=\"12\" fill=\"#222222\">\n";
    auto legend_entry = [&](const std::string& label, auto&& draw_symbol) {
        const std::vector<std::string> lines = wrap(label, 32);
        draw_symbol(lx, ly + 8.0);
        for (std::size_t i = 0; i < lines.size(); ++i) {
            out << "<text x=\"" << num(lx + 40) << "\" y=\"" << num(ly + 12 + 15.0 * i) << "\">"
                << escape(lines[i]) << "</text>\n";
        }
        ly += 15.0 * lines.size() + 7.0;
    };
    for (std::size_t k = 0; k < plot.series.size(); ++k) {
        const Series& s = plot.series[k];
        if (s.label.empty()) continue;
        legend_entry(s.label, [&](double x, double y) {
            if (s.line) {
                out << "<line x1=\"" << num(x) << "\" y1=\"" << num(y) << "\" x2=\"" << num(x + 30)
                    << "\" y2=\"" << num(y) << "\" stroke=\"" << colors[k] << "\" stroke-width=\""
                    << num(s.line_width) << "\"";
                if (!s.dash.empty()) out << " stroke-dasharray=\"" << s.dash << "\"";
                out << "/>\n";
            }
            draw_marker(out, s.marker, x + 15, y, s.marker_size, colors[k], s.hollow);
        });
    }
    for (const EdgeMarkers& e : plot.edges) {
        if (e.label.empty() || e.x.empty()) continue;
        legend_entry(e.label, [&](double x, double y) {
            draw_marker(out, e.marker, x + 15, y, 5.0, e.color, false);
        });
    }
    out << "</g>\n";

    // Notes
    double ny = plot.height - 6.0;
    out << "<g font-size=\"12\" fill=\"#444444\">\n";
    for (const auto& lines : note_lines) {
        for (const std::string& line : lines) {
            out << "<text x=\"12\" y=\"" << num(ny) << "\">" << escape(line) << "</text>\n";
            ny += 17.0;
        }
    }
    out << "</g>\n";
    out << "</svg>\n";
    return out.str();
}

bool write_svg(const std::filesystem::path& path, const Plot& plot) {
    std::ofstream file(path, std::ios::binary);
    if (!file) return false;
    file << render_svg(plot);
    return static_cast<bool>(file);
}

}  // namespace rollgap::tools
