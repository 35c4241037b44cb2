#include "core/spectrum.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.h"

namespace littoral {

Spectrum Spectrum::constant(double v) {
    Spectrum s;
    s.val_ = {v};
    return s;
}

Spectrum Spectrum::tabulated(std::vector<double> wl, std::vector<double> v, const std::string& what) {
    if (wl.empty()) throw InputError(fmt::format("{}: a tabulated spectrum needs at least one wavelength", what));
    if (wl.size() != v.size())
        throw InputError(fmt::format("{}: {} wavelengths but {} values", what, wl.size(), v.size()));
    for (size_t i = 0; i < wl.size(); ++i) {
        if (!std::isfinite(wl[i]) || !std::isfinite(v[i]) || wl[i] <= 0)
            throw InputError(fmt::format("{}: sample {} is not a finite positive wavelength with a finite value", what, i));
        if (i && wl[i] <= wl[i - 1])
            throw InputError(fmt::format("{}: wavelengths must increase strictly (sample {}: {} after {})", what, i,
                                         wl[i], wl[i - 1]));
    }
    Spectrum s;
    s.wl_ = std::move(wl);
    s.val_ = std::move(v);
    return s;
}

double Spectrum::minWavelength() const { return wl_.empty() ? 0.0 : wl_.front(); }
double Spectrum::maxWavelength() const { return wl_.empty() ? INFINITY : wl_.back(); }

bool Spectrum::covers(double lo, double hi) const {
    if (isConstant()) return true;
    const double eps = 1e-9;
    return lo >= wl_.front() - eps && hi <= wl_.back() + eps;
}

double Spectrum::at(double w) const {
    if (isConstant()) return val_.empty() ? 0.0 : val_[0];
    if (!covers(w, w))
        throw InputError(fmt::format("wavelength {} um is outside the tabulated range [{}, {}] um", w, wl_.front(),
                                     wl_.back()));
    if (wl_.size() == 1) return val_[0];
    auto it = std::upper_bound(wl_.begin(), wl_.end(), w);
    size_t i = std::clamp<size_t>(static_cast<size_t>(it - wl_.begin()), 1, wl_.size() - 1) - 1;
    const double t = (w - wl_[i]) / (wl_[i + 1] - wl_[i]);
    return val_[i] + std::clamp(t, 0.0, 1.0) * (val_[i + 1] - val_[i]);
}

double Spectrum::integrate(double lo, double hi) const {
    if (hi <= lo) return 0.0;
    if (isConstant() || wl_.size() == 1) return at(lo) * (hi - lo);
    // Exact integral of the piecewise-linear interpolant: trapezoids between breakpoints.
    std::vector<double> xs{lo};
    for (double w : wl_)
        if (w > lo && w < hi) xs.push_back(w);
    xs.push_back(hi);
    double sum = 0;
    for (size_t i = 1; i < xs.size(); ++i) sum += 0.5 * (at(xs[i - 1]) + at(xs[i])) * (xs[i] - xs[i - 1]);
    return sum;
}

double Spectrum::bandAverage(const Band& b, const std::string& what) const {
    if (!(b.hi > b.lo)) throw InputError(fmt::format("{}: empty band [{}, {}] um", what, b.lo, b.hi));
    if (!covers(b.lo, b.hi))
        throw InputError(fmt::format("{}: band [{}, {}] um lies outside the tabulated range [{}, {}] um", what, b.lo,
                                     b.hi, wl_.front(), wl_.back()));
    if (isConstant()) return at(b.lo);
    if (wl_.size() == 1) return val_[0];
    return integrate(b.lo, b.hi) / (b.hi - b.lo);
}

std::vector<double> Spectrum::bandAverages(const std::vector<Band>& bands, const std::string& what) const {
    std::vector<double> out;
    out.reserve(bands.size());
    for (const auto& b : bands) out.push_back(bandAverage(b, what));
    return out;
}

Spectrum Spectrum::scaled(double s) const {
    Spectrum r = *this;
    for (auto& v : r.val_) v *= s;
    return r;
}

std::vector<Band> uniformBands(double lo, double hi, int n) {
    LITTORAL_CHECK_GT(n, 0);
    LITTORAL_CHECK_GT(hi, lo);
    std::vector<Band> bands(n);
    for (int i = 0; i < n; ++i) bands[i] = {lo + (hi - lo) * i / n, lo + (hi - lo) * (i + 1) / n};
    return bands;
}

}  // namespace littoral
