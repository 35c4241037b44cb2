#pragma once
// Small line charts written as standalone SVG (no plotting library needed): used by the study
// commands for figures a person would rather look at than read (docs/image-quality.md).
#include <string>
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

// The chart as an SVG document. An empty or degenerate data range still gives a valid document.
std::string svgLineChart(const PlotSpec& spec);

}  // namespace littoral::pipelines
