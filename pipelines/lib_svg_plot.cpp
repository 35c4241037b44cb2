#include "pipelines/lib_svg_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace littoral::pipelines {

namespace {

std::string escapeXml(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '<') o += "&lt;";
        else if (c == '>') o += "&gt;";
        else if (c == '&') o += "&amp;";
        else if (c == '"') o += "&quot;";
        else o += c;
    }
    return o;
}

// "Nice" tick positions covering [lo, hi] (about n of them).
std::vector<double> ticks(double lo, double hi, int n) {
    const double span = hi - lo;
    if (!(span > 0)) return {lo};
    const double raw = span / n, mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * mag >= raw) {
            step = m * mag;
            break;
        }
    std::vector<double> t;
    for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) t.push_back(std::abs(v) < 1e-12 * step ? 0 : v);
    return t;
}

const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"};

}  // namespace

std::string svgLineChart(const PlotSpec& p) {
    const double L = 70, R = 150, T = 36, B = 50;  // margins (legend on the right)
    const double W = p.width, H = p.height, pw = W - L - R, ph = H - T - B;
    auto tx = [&](double v) { return p.logX ? std::log10(v) : v; };
    auto ty = [&](double v) { return p.logY ? std::log10(v) : v; };
    auto usable = [&](double x, double y) {
        return std::isfinite(x) && std::isfinite(y) && (!p.logX || x > 0) && (!p.logY || y > 0);
    };
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const auto& s : p.series)
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (usable(s.x[i], s.y[i])) {
                x0 = std::min(x0, tx(s.x[i])), x1 = std::max(x1, tx(s.x[i]));
                y0 = std::min(y0, ty(s.y[i])), y1 = std::max(y1, ty(s.y[i]));
            }
    if (!(x1 >= x0)) x0 = 0, x1 = 1;
    if (!(y1 >= y0)) y0 = 0, y1 = 1;
    if (x1 == x0) x0 -= 0.5, x1 += 0.5;
    if (y1 == y0) y0 -= 0.5 * std::max(1.0, std::abs(y0)), y1 += 0.5 * std::max(1.0, std::abs(y1));
    const double padY = 0.05 * (y1 - y0);
    y0 -= padY, y1 += padY;
    auto px = [&](double v) { return L + (tx(v) - x0) / (x1 - x0) * pw; };
    auto py = [&](double v) { return T + ph - (ty(v) - y0) / (y1 - y0) * ph; };
    std::string o = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
        "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"{0}\" height=\"{1}\" fill=\"white\"/>\n",
        W, H);
    o += fmt::format("<text x=\"{}\" y=\"22\" text-anchor=\"middle\" font-size=\"14\">{}</text>\n", L + pw / 2,
                     escapeXml(p.title));
    o += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>\n", L, T, pw, ph);
    for (double t : ticks(x0, x1, 6)) {
        const double X = L + (t - x0) / (x1 - x0) * pw;
        const double label = p.logX ? std::pow(10.0, t) : t;
        o += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"#ddd\"/>"
                         "<text x=\"{0}\" y=\"{3}\" text-anchor=\"middle\">{4:g}</text>\n",
                         X, T, T + ph, T + ph + 16, label);
    }
    for (double t : ticks(y0, y1, 6)) {
        const double Y = T + ph - (t - y0) / (y1 - y0) * ph;
        const double label = p.logY ? std::pow(10.0, t) : t;
        o += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"#ddd\"/>"
                         "<text x=\"{3}\" y=\"{4}\" text-anchor=\"end\">{5:.4g}</text>\n",
                         L, Y, L + pw, L - 6, Y + 4, label);
    }
    o += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", L + pw / 2, H - 12, escapeXml(p.xLabel));
    o += fmt::format("<text x=\"16\" y=\"{0}\" text-anchor=\"middle\" transform=\"rotate(-90 16 {0})\">{1}</text>\n",
                     T + ph / 2, escapeXml(p.yLabel));
    for (size_t k = 0; k < p.series.size(); ++k) {
        const auto& s = p.series[k];
        const char* col = kColours[k % 8];
        std::string pts;
        for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
            if (usable(s.x[i], s.y[i])) pts += fmt::format("{:.2f},{:.2f} ", px(s.x[i]), py(s.y[i]));
        o += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.6\"{} points=\"{}\"/>\n", col,
                         s.dashed ? " stroke-dasharray=\"5,3\"" : "", pts);
        if (s.markers)
            for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
                if (usable(s.x[i], s.y[i]))
                    o += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\" fill=\"{}\"/>\n", px(s.x[i]), py(s.y[i]), col);
        const double ly = T + 10 + 18 * static_cast<double>(k);
        o += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"{3}\" stroke-width=\"2\"{4}/>"
                         "<text x=\"{5}\" y=\"{6}\">{7}</text>\n",
                         L + pw + 10, ly, L + pw + 30, col, s.dashed ? " stroke-dasharray=\"5,3\"" : "", L + pw + 36,
                         ly + 4, escapeXml(s.label));
    }
    o += "</svg>\n";
    return o;
}

}  // namespace littoral::pipelines
