#include "core/spectral_response.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral {
namespace {

double sigmaOf(const ResponseSpec& r) { return r.fwhm / (2.0 * std::sqrt(2.0 * std::log(2.0))); }

void support(const ResponseSpec& r, double* a, double* b) {
    switch (r.kind) {
        case ResponseSpec::Kind::Rectangle: *a = r.lo, *b = r.hi; return;
        case ResponseSpec::Kind::Gaussian:
            *a = r.centre - kGaussianSupportFwhm * r.fwhm, *b = r.centre + kGaussianSupportFwhm * r.fwhm;
            return;
        case ResponseSpec::Kind::Table: *a = r.wl.front(), *b = r.wl.back(); return;
    }
}

// int_l^h R(x) dx, exact for each kind (a table is linear between its samples).
double integral(const ResponseSpec& r, double l, double h) {
    double a = 0, b = 0;
    support(r, &a, &b);
    l = std::max(l, a), h = std::min(h, b);
    if (!(h > l)) return 0.0;
    switch (r.kind) {
        case ResponseSpec::Kind::Rectangle: return h - l;
        case ResponseSpec::Kind::Gaussian: {
            const double s = sigmaOf(r) * std::sqrt(2.0);
            return 0.5 * s * std::sqrt(M_PI) * (std::erf((h - r.centre) / s) - std::erf((l - r.centre) / s));
        }
        case ResponseSpec::Kind::Table: {
            double sum = 0;
            for (size_t i = 0; i + 1 < r.wl.size(); ++i) {
                const double x0 = std::max(l, r.wl[i]), x1 = std::min(h, r.wl[i + 1]);
                if (!(x1 > x0)) continue;
                const double y0 = responseAt(r, x0), y1 = responseAt(r, x1);
                sum += 0.5 * (y0 + y1) * (x1 - x0);
            }
            return sum;
        }
    }
    return 0.0;
}

}  // namespace

double responseAt(const ResponseSpec& r, double um) {
    switch (r.kind) {
        case ResponseSpec::Kind::Rectangle: return um >= r.lo && um <= r.hi ? 1.0 : 0.0;
        case ResponseSpec::Kind::Gaussian: {
            const double z = (um - r.centre) / sigmaOf(r);
            return std::exp(-0.5 * z * z);
        }
        case ResponseSpec::Kind::Table: {
            if (um < r.wl.front() || um > r.wl.back()) return 0.0;
            const size_t i = static_cast<size_t>(std::upper_bound(r.wl.begin(), r.wl.end(), um) - r.wl.begin());
            if (i >= r.wl.size()) return r.value.back();
            const double t = (um - r.wl[i - 1]) / (r.wl[i] - r.wl[i - 1]);
            return r.value[i - 1] + t * (r.value[i] - r.value[i - 1]);
        }
    }
    return 0.0;
}

Band tableNominalBand(const std::vector<double>& wl, const std::vector<double>& value) {
    double peak = 0, m0 = 0, m1 = 0;
    for (double v : value) peak = std::max(peak, v);
    for (size_t i = 0; i + 1 < wl.size(); ++i) {  // trapezoids of R and of l R
        const double dx = wl[i + 1] - wl[i];
        m0 += 0.5 * (value[i] + value[i + 1]) * dx;
        m1 += 0.5 * (wl[i] * value[i] + wl[i + 1] * value[i + 1]) * dx;
    }
    const double centroid = m1 / m0, half = 0.5 * peak;
    double lo = wl.front(), hi = wl.back();
    for (size_t i = 0; i + 1 < wl.size(); ++i)
        if (value[i] < half && value[i + 1] >= half) {
            lo = wl[i] + (half - value[i]) / (value[i + 1] - value[i]) * (wl[i + 1] - wl[i]);
            break;
        }
    for (size_t i = wl.size() - 1; i > 0; --i)
        if (value[i] < half && value[i - 1] >= half) {
            hi = wl[i] + (half - value[i]) / (value[i - 1] - value[i]) * (wl[i - 1] - wl[i]);
            break;
        }
    const double fwhm = hi - lo;
    return {centroid - 0.5 * fwhm, centroid + 0.5 * fwhm};
}

ResponseGrid responseGrid(const std::vector<ResponseSpec>& specs) {
    // Breaks at every support edge, then equal sub-bands of at most `step` between breaks that lie
    // inside some support.
    double step = kMaxSubBandUm;
    std::set<double> breaks;
    for (const ResponseSpec& r : specs) {
        double a = 0, b = 0;
        support(r, &a, &b);
        breaks.insert(a), breaks.insert(b);
        if (r.kind == ResponseSpec::Kind::Gaussian) step = std::min(step, r.fwhm / 4);
    }
    ResponseGrid g;
    const std::vector<double> edges(breaks.begin(), breaks.end());
    size_t count = 0;
    for (size_t k = 0; k + 1 < edges.size(); ++k) {
        const double l = edges[k], h = edges[k + 1], mid = 0.5 * (l + h);
        bool covered = false;
        for (const ResponseSpec& r : specs) {
            double a = 0, b = 0;
            support(r, &a, &b);
            covered = covered || (mid > a && mid < b);
        }
        if (!covered) continue;
        const int n = std::max(1, static_cast<int>(std::ceil((h - l) / step - 1e-9)));
        count += static_cast<size_t>(n);
        if (count > static_cast<size_t>(kMaxInternalBands))
            throw InputError(fmt::format("these bands need more than {} internal sub-bands of at most {:g} nm; narrow the "
                                         "responses or widen the narrowest Gaussian",
                                         kMaxInternalBands, step * 1e3));
        for (int i = 0; i < n; ++i) g.internal.push_back({l + (h - l) * i / n, l + (h - l) * (i + 1) / n});
    }
    for (const ResponseSpec& r : specs) {
        ir::ResponseBand out;
        out.kind = r.kind == ResponseSpec::Kind::Rectangle ? "rectangle" : r.kind == ResponseSpec::Kind::Gaussian ? "gaussian" : "table";
        out.nominal = r.kind == ResponseSpec::Kind::Rectangle ? Band{r.lo, r.hi}
                      : r.kind == ResponseSpec::Kind::Gaussian ? Band{r.centre - 0.5 * r.fwhm, r.centre + 0.5 * r.fwhm}
                                                               : tableNominalBand(r.wl, r.value);
        double total = 0;
        for (size_t i = 0; i < g.internal.size(); ++i) {
            const double w = integral(r, g.internal[i].lo, g.internal[i].hi);
            if (w > 0) out.weights.push_back({static_cast<int>(i), w}), total += w;
        }
        LITTORAL_CHECK(total > 0);
        for (auto& [i, w] : out.weights) w /= total;
        g.outputs.push_back(std::move(out));
    }
    return g;
}

}  // namespace littoral
