#pragma once
// Charts drawn with matplotlib (Debian's python3-matplotlib, run as a child process): the study,
// column and validate commands' figures a person would rather look at than read. The data of each
// folder's charts is also written as charts.json with the script that draws them
// (littoral_plots.py, pipelines/plots/), so that a user can redraw or restyle them.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace littoral::pipelines {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;  // same length; non-finite points are skipped
    std::vector<double> yErr;  // empty, or one error bar (one standard error, say) per point
    bool markers = true;
    bool dashed = false;
    bool line = true;  // false: markers only (measured points against a drawn prediction)
    int colour = -1;   // >= 0: the n-th colour of matplotlib's cycle (a prediction and its points alike)
};

struct PlotSpec {
    std::string title, xLabel, yLabel;
    bool logX = false, logY = false;  // log10 axes (non-positive values are skipped)
    bool invertY = false;             // depth profiles: depth increasing downwards
    std::vector<PlotSeries> series;
};

// A chart with its axes and no series yet, and an empty series (all fields set: the build uses
// -Wextra's missing-field-initializers).
inline PlotSpec plotSpec(std::string title, std::string xLabel, std::string yLabel, bool logX = false, bool logY = false) {
    return PlotSpec{std::move(title), std::move(xLabel), std::move(yLabel), logX, logY, false, {}};
}
inline PlotSeries plotSeries(std::string label) { return PlotSeries{std::move(label), {}, {}, {}, true, false, true, -1}; }

struct Chart {
    std::string file;  // e.g. "snr_vs_radius.png", in the folder given to drawCharts
    PlotSpec spec;
};

// Writes folder/charts.json and folder/littoral_plots.py, then draws every chart as folder/<file>
// (PNG) with matplotlib; each file is written atomically (core/atomic_file.h). Returns "" when all
// were drawn, otherwise why none was (no python3 with matplotlib: the apt package to install; the
// script's own error). The interpreter is $LITTORAL_PYTHON, else /usr/bin/python3, else python3
// on PATH.
std::string drawCharts(const std::filesystem::path& folder, const std::vector<Chart>& charts);

}  // namespace littoral::pipelines
