#include "core/colour.h"

#include <algorithm>
#include <cmath>

namespace littoral {
namespace {

// CIE 1931 2-degree standard colorimetric observer, 380-780 nm every 5 nm (CIE 15:2004,
// Table T.4): xbar, ybar, zbar.
constexpr double kCmf[81][3] = {
    {0.001368, 0.000039, 0.006450}, {0.002236, 0.000064, 0.010550}, {0.004243, 0.000120, 0.020050},
    {0.007650, 0.000217, 0.036210}, {0.014310, 0.000396, 0.067850}, {0.023190, 0.000640, 0.110200},
    {0.043510, 0.001210, 0.207400}, {0.077630, 0.002180, 0.371300}, {0.134380, 0.004000, 0.645600},
    {0.214770, 0.007300, 1.039050}, {0.283900, 0.011600, 1.385600}, {0.328500, 0.016840, 1.622960},
    {0.348280, 0.023000, 1.747060}, {0.348060, 0.029800, 1.782600}, {0.336200, 0.038000, 1.772110},
    {0.318700, 0.048000, 1.744100}, {0.290800, 0.060000, 1.669200}, {0.251100, 0.073900, 1.528100},
    {0.195360, 0.090980, 1.287640}, {0.142100, 0.112600, 1.041900}, {0.095640, 0.139020, 0.812950},
    {0.058010, 0.169300, 0.616200}, {0.032010, 0.208020, 0.465180}, {0.014700, 0.258600, 0.353300},
    {0.004900, 0.323000, 0.272000}, {0.002400, 0.407300, 0.212300}, {0.009300, 0.503000, 0.158200},
    {0.029100, 0.608200, 0.111700}, {0.063270, 0.710000, 0.078250}, {0.109600, 0.793200, 0.057250},
    {0.165500, 0.862000, 0.042160}, {0.225750, 0.914850, 0.029840}, {0.290400, 0.954000, 0.020300},
    {0.359700, 0.980300, 0.013400}, {0.433450, 0.994950, 0.008750}, {0.512050, 1.000000, 0.005750},
    {0.594500, 0.995000, 0.003900}, {0.678400, 0.978600, 0.002750}, {0.762100, 0.952000, 0.002100},
    {0.842500, 0.915400, 0.001800}, {0.916300, 0.870000, 0.001650}, {0.978600, 0.816300, 0.001400},
    {1.026300, 0.757000, 0.001100}, {1.056700, 0.694900, 0.001000}, {1.062200, 0.631000, 0.000800},
    {1.045600, 0.566800, 0.000600}, {1.002600, 0.503000, 0.000340}, {0.938400, 0.441200, 0.000240},
    {0.854450, 0.381000, 0.000190}, {0.751400, 0.321000, 0.000100}, {0.642400, 0.265000, 0.000050},
    {0.541900, 0.217000, 0.000030}, {0.447900, 0.175000, 0.000020}, {0.360800, 0.138200, 0.000010},
    {0.283500, 0.107000, 0.000000}, {0.218700, 0.081600, 0.000000}, {0.164900, 0.061000, 0.000000},
    {0.121200, 0.044580, 0.000000}, {0.087400, 0.032000, 0.000000}, {0.063600, 0.023200, 0.000000},
    {0.046770, 0.017000, 0.000000}, {0.032900, 0.011920, 0.000000}, {0.022700, 0.008210, 0.000000},
    {0.015840, 0.005723, 0.000000}, {0.011359, 0.004102, 0.000000}, {0.008111, 0.002929, 0.000000},
    {0.005790, 0.002091, 0.000000}, {0.004109, 0.001484, 0.000000}, {0.002899, 0.001047, 0.000000},
    {0.002049, 0.000740, 0.000000}, {0.001440, 0.000520, 0.000000}, {0.001000, 0.000361, 0.000000},
    {0.000690, 0.000249, 0.000000}, {0.000476, 0.000172, 0.000000}, {0.000332, 0.000120, 0.000000},
    {0.000235, 0.000085, 0.000000}, {0.000166, 0.000060, 0.000000}, {0.000117, 0.000042, 0.000000},
    {0.000083, 0.000030, 0.000000}, {0.000059, 0.000021, 0.000000}, {0.000042, 0.000015, 0.000000},
};
constexpr double kCmfFirstNm = 380.0, kCmfStepNm = 5.0;
constexpr int kCmfCount = 81;

// The integration grid: 0.5 nm over the table's range (trapezoids of a piecewise-linear
// integrand with kinks at band edges: the error is far below the 8-bit preview's resolution).
constexpr double kGridNm = 0.5;
constexpr int kGridCount = static_cast<int>((kCmfStepNm * (kCmfCount - 1)) / kGridNm) + 1;

double gridUm(int i) { return 1e-3 * (kCmfFirstNm + kGridNm * i); }
double gridWeight(int i) { return (i == 0 || i == kGridCount - 1 ? 0.5 : 1.0) * kGridNm * 1e-3; }

// The reconstruction at `um` as at most two (band, coefficient) pairs; returns the count.
int reconstruction(const std::vector<Band>& sorted, double um, int band[], double coef[]) {
    const int n = static_cast<int>(sorted.size());
    int inside = 0;
    for (int b = 0; b < n && inside < 2; ++b)
        if (um >= sorted[b].lo && um < sorted[b].hi) band[inside++] = b;
    if (inside > 0) {
        for (int k = 0; k < inside; ++k) coef[k] = 1.0 / inside;
        return inside;
    }
    if (um < sorted.front().lo) return band[0] = 0, coef[0] = 1.0, 1;
    int below = -1;  // the last band ending at or before um
    for (int b = 0; b < n; ++b)
        if (sorted[b].hi <= um && (below < 0 || sorted[b].hi > sorted[below].hi)) below = b;
    int above = -1;  // the first band starting after um
    for (int b = 0; b < n; ++b)
        if (sorted[b].lo > um && (above < 0 || sorted[b].lo < sorted[above].lo)) above = b;
    if (above < 0) return band[0] = below, coef[0] = 1.0, 1;
    const double t = (um - sorted[below].hi) / (sorted[above].lo - sorted[below].hi);
    band[0] = below, coef[0] = 1.0 - t;
    band[1] = above, coef[1] = t;
    return 2;
}

Xyz cmfIntegral(double loUm, double hiUm) {
    Xyz s;
    for (int i = 0; i < kGridCount; ++i) {
        const double um = gridUm(i);
        if (um < loUm || um > hiUm) continue;
        const Xyz c = cieCmf(um);
        const double w = gridWeight(i);
        s.x += w * c.x, s.y += w * c.y, s.z += w * c.z;
    }
    return s;
}

}  // namespace

Xyz cieCmf(double um) {
    const double f = (um * 1e3 - kCmfFirstNm) / kCmfStepNm;
    if (!(f >= 0.0) || f > kCmfCount - 1) return {};
    const int i = std::min(static_cast<int>(f), kCmfCount - 2);
    const double t = f - i;
    return {kCmf[i][0] + t * (kCmf[i + 1][0] - kCmf[i][0]), kCmf[i][1] + t * (kCmf[i + 1][1] - kCmf[i][1]),
            kCmf[i][2] + t * (kCmf[i + 1][2] - kCmf[i][2])};
}

std::vector<Xyz> xyzBandWeights(const std::vector<Band>& bands) {
    std::vector<int> order(bands.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return bands[a].center() < bands[b].center(); });
    std::vector<Band> sorted;
    for (int i : order) sorted.push_back(bands[static_cast<size_t>(i)]);
    std::vector<Xyz> w(bands.size());
    if (bands.empty()) return w;
    const double yFlat = cmfIntegral(0.0, 1.0).y;  // Y of a flat spectrum of 1
    for (int i = 0; i < kGridCount; ++i) {
        int band[2];
        double coef[2];
        const int k = reconstruction(sorted, gridUm(i), band, coef);
        const Xyz c = cieCmf(gridUm(i));
        const double dw = gridWeight(i) / yFlat;
        for (int j = 0; j < k; ++j) {
            Xyz& o = w[static_cast<size_t>(order[static_cast<size_t>(band[j])])];
            o.x += dw * coef[j] * c.x, o.y += dw * coef[j] * c.y, o.z += dw * coef[j] * c.z;
        }
    }
    return w;
}

double visibleCoverage(const std::vector<Band>& bands) {
    if (bands.empty()) return 0.0;
    double lo = bands[0].lo, hi = bands[0].hi;
    for (const Band& b : bands) lo = std::min(lo, b.lo), hi = std::max(hi, b.hi);
    const Xyz all = cmfIntegral(0.0, 1.0), in = cmfIntegral(lo, hi);
    return std::min({in.x / all.x, in.y / all.y, in.z / all.z});
}

bool spansVisible(const std::vector<Band>& bands) {
    return bands.size() >= 3 && visibleCoverage(bands) >= kVisibleCoverage;
}

std::array<double, 3> xyzToLinearSrgb(const Xyz& c) {
    return {3.2406 * c.x - 1.5372 * c.y - 0.4986 * c.z, -0.9689 * c.x + 1.8758 * c.y + 0.0415 * c.z,
            0.0557 * c.x - 0.2040 * c.y + 1.0570 * c.z};
}

Xyz linearSrgbToXyz(const std::array<double, 3>& v) {
    return {0.4124 * v[0] + 0.3576 * v[1] + 0.1805 * v[2], 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2],
            0.0193 * v[0] + 0.1192 * v[1] + 0.9505 * v[2]};
}

double srgbEncode(double v) {
    v = std::clamp(v, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

double srgbDecode(double e) {
    e = std::clamp(e, 0.0, 1.0);
    return e <= 0.04045 ? e / 12.92 : std::pow((e + 0.055) / 1.055, 2.4);
}

std::array<double, 2> chromaticity(const Xyz& c) {
    const double s = c.x + c.y + c.z;
    if (!(s > 0)) return {0.0, 0.0};
    return {c.x / s, c.y / s};
}

}  // namespace littoral
