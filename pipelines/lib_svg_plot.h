#pragma once
// Small line charts written as standalone SVG (no plotting library needed): used by the study
// commands for figures a person would rather look at than read (docs/image-quality.md).
#include <string>
#include <utility>
#include <vector>

namespace littoral::pipelines {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;  // same length; non-finite points are skipped
    bool markers = true;
    bool dashed = false;
};

struct PlotSpec {
    std::string title, xLabel, yLabel;
    bool logX = false, logY = false;  // log10 axes (non-positive values are skipped)
    int width = 560, height = 380;    // pixels
    std::vector<PlotSeries> series;
};

// A chart with its axes and no series yet, and an empty series (all fields set: the build uses
// -Wextra's missing-field-initializers).
inline PlotSpec plotSpec(std::string title, std::string xLabel, std::string yLabel, bool logX = false, bool logY = false) {
    return PlotSpec{std::move(title), std::move(xLabel), std::move(yLabel), logX, logY, 560, 380, {}};
}
inline PlotSeries plotSeries(std::string label) { return PlotSeries{std::move(label), {}, {}, true, false}; }

// The chart as an SVG document. An empty or degenerate data range still gives a valid document.
std::string svgLineChart(const PlotSpec& spec);

}  // namespace littoral::pipelines
