// A small SVG writer for `wsd bench`: error against time on log–log axes, one polyline <path>
// per series (knob) with a legend, the Pareto front over all points marked, axis labels and
// decade ticks. The output is well-formed XML (all text escaped).
#pragma once

#include <string>
#include <vector>

namespace wsd::app {

struct PlotPoint {
    double x = 0, y = 0;  // must be > 0 to be plotted on log axes; smaller y is clamped
    std::string label;
};

struct PlotSeries {
    std::string name;
    std::vector<PlotPoint> points;  // joined in this order
};

struct PlotLabels {
    std::string title, x_axis, y_axis;
};

std::string svg_log_log_plot(const std::vector<PlotSeries>& series, const PlotLabels& labels);

// Indices (series, point) of the points no other point beats on both x and y, sorted by x.
std::vector<std::pair<size_t, size_t>> pareto_front(const std::vector<PlotSeries>& series);

std::string xml_escape(const std::string& text);

}  // namespace wsd::app
