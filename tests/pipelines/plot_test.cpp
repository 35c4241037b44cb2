// The charts of pipelines/lib_plot.h, drawn with matplotlib: PNGs with their data beside them; a
// legend outside the axes widens the image instead of being cut; NaN stays out of the data; a
// missing interpreter is a message, not a failure, and leaves the data.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "pipelines/lib_plot.h"
#include "tests/support/test_support.h"

namespace fs = std::filesystem;
namespace lp = littoral::pipelines;
using namespace littoral::testing_support;

namespace {

lp::PlotSpec logChart(bool legend) {
    lp::PlotSpec p = lp::plotSpec("SNR against search radius", "search radius (m)", "SNR", true, true);
    lp::PlotSeries s = lp::plotSeries(legend ? "bright side, target 3.5 m deep, 3000 photons per m^3" : "");
    s.x = {0.1, 0.25, 0.5, 1.0, 2.0};
    s.y = {3.0, 12.0, NAN, 40.0, 90.0};
    s.yErr = {0.5, 1.0, 1.0, 2.0, 3.0};
    p.series.push_back(s);
    return p;
}

}  // namespace

TEST(Plots, DrawsPngsWithTheirDataAndKeepsTheLegendInside) {
    const fs::path dir = scratchDir("plots", "draw");
    ASSERT_EQ(lp::drawCharts(dir, {{"with_legend.png", logChart(true)}, {"without.png", logChart(false)}}), "");
    const auto [w1, h1] = pngSize(dir / "with_legend.png");
    const auto [w0, h0] = pngSize(dir / "without.png");
    EXPECT_GT(w0, 500u);
    EXPECT_GT(h0, 300u);
    // The legend sits right of the axes and the figure is cropped to what is drawn, so the image
    // grows by the legend's width (its 50-character label is well over 150 px at 8 pt).
    EXPECT_GT(w1, w0 + 150) << w1 << " vs " << w0;
    const auto j = nlohmann::json::parse(littoral::readTextFile(dir / "charts.json"));
    ASSERT_EQ(j.size(), 2u);
    EXPECT_TRUE(j[0]["series"][0]["y"][2].is_null());
    EXPECT_TRUE(j[0]["logx"].get<bool>());
    EXPECT_TRUE(fs::is_regular_file(dir / "littoral_plots.py"));
}

TEST(Plots, AMissingInterpreterIsAMessageAndTheDataStays) {
    const fs::path dir = scratchDir("plots", "missing");
    setenv("LITTORAL_PYTHON", "/nonexistent/python3", 1);
    const std::string why = lp::drawCharts(dir, {{"a.png", logChart(true)}});
    unsetenv("LITTORAL_PYTHON");
    EXPECT_NE(why.find("plots not drawn"), std::string::npos) << why;
    EXPECT_NE(why.find("python3-matplotlib"), std::string::npos) << why;
    EXPECT_FALSE(fs::exists(dir / "a.png"));
    EXPECT_TRUE(fs::is_regular_file(dir / "charts.json"));
}
