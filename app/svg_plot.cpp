// The bench plot. Coordinates are computed in log10 space and printed with fixed decimals; each
// series gets one <path> (class "series"), the Pareto front a dashed <polyline> (class "pareto"),
// so that the file can be checked by counting elements.
#include "app/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace wsd::app {

namespace {

constexpr double plot_w = 720, plot_h = 480;
constexpr double left = 80, right = 220, top = 50, bottom = 60;  // margins; legend on the right
const char* const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                               "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", v);
    return buf;
}

std::string tick_label(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

struct LogAxis {
    double lo = 0, hi = 1;  // log10 of the range ends (whole decades)
    double pixel_lo = 0, pixel_hi = 1;
    double map(double v) const {
        const double t = (std::log10(v) - lo) / (hi - lo);
        return pixel_lo + t * (pixel_hi - pixel_lo);
    }
};

LogAxis make_axis(double min_v, double max_v, double pixel_lo, double pixel_hi) {
    LogAxis a;
    a.lo = std::floor(std::log10(min_v));
    a.hi = std::ceil(std::log10(max_v));
    if (a.hi <= a.lo) a.hi = a.lo + 1;
    a.pixel_lo = pixel_lo;
    a.pixel_hi = pixel_hi;
    return a;
}

// Ticks at every decade, and at 2 and 5 times each decade when the axis spans few decades.
std::vector<double> ticks(const LogAxis& a) {
    std::vector<double> out;
    const bool fine = a.hi - a.lo <= 2;
    for (int e = static_cast<int>(a.lo); e <= static_cast<int>(a.hi); ++e) {
        const double decade = std::pow(10.0, e);
        out.push_back(decade);
        if (fine && e < static_cast<int>(a.hi)) {
            out.push_back(2 * decade);
            out.push_back(5 * decade);
        }
    }
    return out;
}

}  // namespace

std::string xml_escape(const std::string& text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            case '\'':
                out += "&apos;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

std::vector<std::pair<size_t, size_t>> pareto_front(const std::vector<PlotSeries>& series) {
    std::vector<std::pair<size_t, size_t>> all;
    for (size_t s = 0; s < series.size(); ++s)
        for (size_t p = 0; p < series[s].points.size(); ++p) all.emplace_back(s, p);
    auto at = [&](const std::pair<size_t, size_t>& i) -> const PlotPoint& {
        return series[i.first].points[i.second];
    };
    std::vector<std::pair<size_t, size_t>> front;
    for (const auto& i : all) {
        const PlotPoint& a = at(i);
        const bool dominated = std::any_of(all.begin(), all.end(), [&](const auto& j) {
            const PlotPoint& b = at(j);
            return b.x <= a.x && b.y <= a.y && (b.x < a.x || b.y < a.y);
        });
        if (!dominated) front.push_back(i);
    }
    std::sort(front.begin(), front.end(), [&](const auto& i, const auto& j) { return at(i).x < at(j).x; });
    return front;
}

std::string svg_log_log_plot(const std::vector<PlotSeries>& series, const PlotLabels& labels) {
    // Non-positive values cannot sit on a log axis: clamp them to a floor below the smallest.
    double min_x = std::numeric_limits<double>::infinity(), max_x = 0;
    double min_y = std::numeric_limits<double>::infinity(), max_y = 0;
    for (const PlotSeries& s : series)
        for (const PlotPoint& p : s.points) {
            if (p.x > 0) min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
            if (p.y > 0) min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
        }
    if (!std::isfinite(min_x)) min_x = max_x = 1;
    if (!std::isfinite(min_y)) min_y = max_y = 1;
    const double floor_x = min_x / 2, floor_y = min_y / 2;
    std::vector<PlotSeries> clamped = series;
    for (PlotSeries& s : clamped)
        for (PlotPoint& p : s.points) {
            if (!(p.x > 0)) p.x = floor_x;
            if (!(p.y > 0)) p.y = floor_y;
        }
    auto any_nonpositive = [&](double PlotPoint::*member) {
        return std::any_of(series.begin(), series.end(), [&](const PlotSeries& s) {
            return std::any_of(s.points.begin(), s.points.end(),
                               [&](const PlotPoint& p) { return !(p.*member > 0); });
        });
    };
    const bool any_floor_x = any_nonpositive(&PlotPoint::x), any_floor_y = any_nonpositive(&PlotPoint::y);
    const LogAxis ax = make_axis(any_floor_x ? floor_x : min_x, max_x, left, plot_w - right);
    const LogAxis ay = make_axis(any_floor_y ? floor_y : min_y, max_y, plot_h - bottom, top);

    std::ostringstream out;
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << plot_w << "\" height=\"" << plot_h
        << "\" viewBox=\"0 0 " << plot_w << " " << plot_h
        << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
        << "<title>" << xml_escape(labels.title) << "</title>\n"
        << "<rect x=\"0\" y=\"0\" width=\"" << plot_w << "\" height=\"" << plot_h << "\" fill=\"white\"/>\n"
        << "<text x=\"" << num((left + plot_w - right) / 2)
        << "\" y=\"24\" text-anchor=\"middle\" font-size=\"15\">" << xml_escape(labels.title) << "</text>\n";
    // Axes, grid and ticks.
    out << "<g class=\"axes\" stroke=\"black\">\n"
        << "<line x1=\"" << left << "\" y1=\"" << plot_h - bottom << "\" x2=\"" << plot_w - right
        << "\" y2=\"" << plot_h - bottom << "\"/>\n"
        << "<line x1=\"" << left << "\" y1=\"" << top << "\" x2=\"" << left << "\" y2=\"" << plot_h - bottom
        << "\"/>\n"
        << "</g>\n<g class=\"ticks\" font-size=\"10\">\n";
    for (const double t : ticks(ax)) {
        const double x = ax.map(t);
        out << "<line x1=\"" << num(x) << "\" y1=\"" << plot_h - bottom << "\" x2=\"" << num(x) << "\" y2=\""
            << plot_h - bottom + 5 << "\" stroke=\"black\"/>"
            << "<line x1=\"" << num(x) << "\" y1=\"" << top << "\" x2=\"" << num(x) << "\" y2=\""
            << plot_h - bottom << "\" stroke=\"#dddddd\"/>"
            << "<text x=\"" << num(x) << "\" y=\"" << plot_h - bottom + 17 << "\" text-anchor=\"middle\">"
            << xml_escape(tick_label(t)) << "</text>\n";
    }
    for (const double t : ticks(ay)) {
        const double y = ay.map(t);
        out << "<line x1=\"" << left - 5 << "\" y1=\"" << num(y) << "\" x2=\"" << left << "\" y2=\"" << num(y)
            << "\" stroke=\"black\"/>"
            << "<line x1=\"" << left << "\" y1=\"" << num(y) << "\" x2=\"" << plot_w - right << "\" y2=\""
            << num(y) << "\" stroke=\"#dddddd\"/>"
            << "<text x=\"" << left - 8 << "\" y=\"" << num(y + 3) << "\" text-anchor=\"end\">"
            << xml_escape(tick_label(t)) << "</text>\n";
    }
    out << "</g>\n"
        << "<text x=\"" << num((left + plot_w - right) / 2) << "\" y=\"" << plot_h - 15
        << "\" text-anchor=\"middle\">" << xml_escape(labels.x_axis) << "</text>\n"
        << "<text x=\"18\" y=\"" << num((top + plot_h - bottom) / 2)
        << "\" text-anchor=\"middle\" transform=\"rotate(-90 18 " << num((top + plot_h - bottom) / 2)
        << ")\">" << xml_escape(labels.y_axis) << "</text>\n";
    // One path per series, with a marker at each point.
    for (size_t s = 0; s < clamped.size(); ++s) {
        const char* colour = palette[s % (sizeof palette / sizeof palette[0])];
        std::string d;
        for (size_t p = 0; p < clamped[s].points.size(); ++p)
            d += (p ? " L " : "M ") + num(ax.map(clamped[s].points[p].x)) + " " +
                 num(ay.map(clamped[s].points[p].y));
        out << "<path class=\"series\" data-series=\"" << xml_escape(clamped[s].name) << "\" d=\"" << d
            << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"1.5\"/>\n";
        // Each point names its value beside it, so the picture reads without the table (and
        // without hovering, which an <img> in a README does not offer).
        for (const PlotPoint& p : clamped[s].points)
            out << "<circle cx=\"" << num(ax.map(p.x)) << "\" cy=\"" << num(ay.map(p.y))
                << "\" r=\"3\" fill=\"" << colour << "\"><title>"
                << xml_escape(clamped[s].name + " " + p.label) << "</title></circle>\n"
                << "<text class=\"value\" x=\"" << num(ax.map(p.x) + 5) << "\" y=\"" << num(ay.map(p.y) - 5)
                << "\" font-size=\"9\" fill=\"" << colour << "\">" << xml_escape(p.label) << "</text>\n";
    }
    // The Pareto front: the settings nothing beats on both time and error.
    const auto front = pareto_front(clamped);
    out << "<polyline class=\"pareto\" points=\"";
    for (size_t i = 0; i < front.size(); ++i) {
        const PlotPoint& p = clamped[front[i].first].points[front[i].second];
        out << (i ? " " : "") << num(ax.map(p.x)) << "," << num(ay.map(p.y));
    }
    out << "\" fill=\"none\" stroke=\"black\" stroke-dasharray=\"5,4\" stroke-width=\"1\"/>\n";
    for (const auto& [s, i] : front) {
        const PlotPoint& p = clamped[s].points[i];
        out << "<circle class=\"pareto-point\" cx=\"" << num(ax.map(p.x)) << "\" cy=\"" << num(ay.map(p.y))
            << "\" r=\"6\" fill=\"none\" stroke=\"black\"/>\n";
    }
    // Legend.
    const double lx = plot_w - right + 20;
    out << "<g class=\"legend\">\n";
    for (size_t s = 0; s < clamped.size(); ++s) {
        const double y = top + 10 + 20.0 * static_cast<double>(s);
        out << "<rect x=\"" << lx << "\" y=\"" << num(y - 8) << "\" width=\"14\" height=\"10\" fill=\""
            << palette[s % (sizeof palette / sizeof palette[0])] << "\"/><text x=\"" << lx + 20 << "\" y=\""
            << num(y + 1) << "\">" << xml_escape(clamped[s].name) << "</text>\n";
    }
    const double py = top + 10 + 20.0 * static_cast<double>(clamped.size());
    out << "<line x1=\"" << lx << "\" y1=\"" << num(py - 3) << "\" x2=\"" << lx + 14 << "\" y2=\""
        << num(py - 3) << "\" stroke=\"black\" stroke-dasharray=\"5,4\"/><text x=\"" << lx + 20 << "\" y=\""
        << num(py + 1) << "\">Pareto front</text>\n";
    if (any_floor_y)
        out << "<text x=\"" << lx << "\" y=\"" << num(py + 20) << "\" font-size=\"10\">error 0 drawn at "
            << xml_escape(tick_label(floor_y)) << "</text>\n";
    out << "</g>\n</svg>\n";
    return out.str();
}

}  // namespace wsd::app
