// Analytic terrains: planar slope, Dean equilibrium profile, bar and trough.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bathymetry/param_check.h"
#include "bathymetry/terrain.h"
#include "core/units.h"

namespace littoral::bathymetry {

using detail::require;
using detail::requireFinite;
using detail::requireNonNegative;
using detail::requirePositive;

namespace {

void checkExtent(std::string_view what, const Extent& e) {
    for (double v : {e.x0, e.y0, e.x1, e.y1}) requireFinite(what, "extent", v);
    if (!e.valid())
        throw InputError(fmt::format("{}.extent = [{}, {}] x [{}, {}] m: must have x0 < x1 and y0 < y1", what,
                                     e.x0, e.x1, e.y0, e.y1));
}

class PlanarTerrain final : public Terrain {
public:
    PlanarTerrain(const Extent& e, const PlanarSlope& p) : e_(e), p_(p) {}
    double elevation(double x, double y) const override { return p_.z0 + p_.slopeX * x + p_.slopeY * y; }
    Extent extent() const override { return e_; }
    std::string describe() const override {
        return fmt::format("planar slope z = {} + {} x + {} y m", p_.z0, p_.slopeX, p_.slopeY);
    }

private:
    Extent e_;
    PlanarSlope p_;
};

void checkDean(std::string_view what, const DeanProfile& p) {
    // A spans about 0.02 (fine silt) to 0.6 m^(1/3) (cobbles) in Dean (1987) / Moore (1982).
    require(std::isfinite(p.A) && p.A > 0 && p.A <= 2, what, "A", p.A, "in (0, 2] m^(1/3)");
    requireFinite(what, "shoreline_x_m", p.shorelineX);
    require(std::isfinite(p.beachSlope) && p.beachSlope > 0 && p.beachSlope <= 1, what, "beach_slope",
            p.beachSlope, "in (0, 1] (dz/dx of the beach face)");
    requireNonNegative(what, "berm_height_m", p.bermHeight);
    require(p.maxDepth > 0, what, "max_depth_m", p.maxDepth, "> 0 m (or infinite)");
    requireNonNegative(what, "dune_height_m", p.duneHeight);
    requireNonNegative(what, "dune_offset_m", p.duneOffset);
    requirePositive(what, "dune_width_m", p.duneWidth);
}

// Elevation of the Dean profile at signed offshore distance d (metres; d > 0 is sea).
double deanElevation(const DeanProfile& p, double d) {
    if (d >= 0) return -std::min(p.A * std::cbrt(d * d), p.maxDepth);  // Dean (1991) eq. 1: h = A d^(2/3)
    const double land = -d;                                             // metres landward of the shoreline
    double z = std::min(p.beachSlope * land, p.bermHeight);             // planar beach face, then berm
    if (p.duneHeight > p.bermHeight) {
        const double start = p.bermHeight / p.beachSlope + p.duneOffset;  // berm crest + offset
        const double u = std::clamp((land - start) / p.duneWidth, 0.0, 1.0);
        z += (p.duneHeight - p.bermHeight) * 0.5 * (1 - std::cos(kPi * u));  // cosine ramp, C1 at both ends
    }
    return z;
}

double offshoreDistance(const DeanProfile& p, double x) {
    return p.offshoreTowardPositiveX ? x - p.shorelineX : p.shorelineX - x;
}

class DeanTerrain final : public Terrain {
public:
    DeanTerrain(const Extent& e, const DeanProfile& p) : e_(e), p_(p) {}
    double elevation(double x, double /*y*/) const override { return deanElevation(p_, offshoreDistance(p_, x)); }
    Extent extent() const override { return e_; }
    std::string describe() const override {
        return fmt::format("Dean profile A = {} m^(1/3), shoreline x = {} m (offshore toward {}x), beach slope {}, "
                           "berm {} m", p_.A, p_.shorelineX, p_.offshoreTowardPositiveX ? "+" : "-", p_.beachSlope,
                           p_.bermHeight);
    }

private:
    Extent e_;
    DeanProfile p_;
};

class BarTroughTerrain final : public Terrain {
public:
    BarTroughTerrain(const Extent& e, const BarTrough& p) : e_(e), p_(p) {}

    double elevation(double x, double y) const override {
        const double d = offshoreDistance(p_.dean, x);
        return deanElevation(p_.dean, d) + perturbation(d, y);
    }
    Extent extent() const override { return e_; }
    std::string describe() const override {
        return fmt::format("bar-trough on Dean profile A = {} m^(1/3): bar {} m high at {} m offshore (sigma {} m), "
                           "trough {} m deep at {} m (sigma {} m), crescent amplitude {} m",
                           p_.dean.A, p_.barHeight, p_.barCrestDistance, p_.barWidth, p_.troughDepth,
                           p_.troughDistance, p_.troughWidth, p_.crescentAmplitude);
    }

    // Bar minus trough, ramped in from the shoreline (see terrain.h).
    double perturbation(double d, double y) const {
        if (d <= 0) return 0;
        const double t = std::min(d / (0.5 * p_.troughDistance), 1.0);
        const double ramp = t * t * (3 - 2 * t);
        const double shift = p_.crescentAmplitude * std::sin(2 * kPi * (y - e_.y0) / p_.crescentWavelength);
        const double gb = std::exp(-sqr(d - p_.barCrestDistance - shift) / (2 * sqr(p_.barWidth)));
        const double gt = std::exp(-sqr(d - p_.troughDistance - shift) / (2 * sqr(p_.troughWidth)));
        return ramp * (p_.barHeight * gb - p_.troughDepth * gt);
    }

private:
    Extent e_;
    BarTrough p_;
};

}  // namespace

std::unique_ptr<Terrain> makePlanarSlope(const Extent& extent, const PlanarSlope& p) {
    checkExtent("planar_slope", extent);
    requireFinite("planar_slope", "z0_m", p.z0);
    requireFinite("planar_slope", "slope_x", p.slopeX);
    requireFinite("planar_slope", "slope_y", p.slopeY);
    return std::make_unique<PlanarTerrain>(extent, p);
}

std::unique_ptr<Terrain> makePlanarSlope(const Extent& extent, double z0, double slopeX, double slopeY) {
    return makePlanarSlope(extent, PlanarSlope{z0, slopeX, slopeY});
}

double deanScaleFromGrainSize(double grainSizeMm) {
    require(std::isfinite(grainSizeMm) && grainSizeMm >= 0.05 && grainSizeMm <= 5, "dean", "grain_size_mm",
            grainSizeMm, "in [0.05, 5] mm (sand to fine gravel, the range of the A(D) fit)");
    return 0.21 * std::pow(grainSizeMm, 0.48);  // Dean (1987) fit to Moore (1982): A [m^(1/3)], D [mm]
}

std::unique_ptr<Terrain> makeDeanProfile(const Extent& extent, const DeanProfile& p) {
    checkExtent("dean", extent);
    checkDean("dean", p);
    return std::make_unique<DeanTerrain>(extent, p);
}

std::unique_ptr<Terrain> makeDeanProfile(const Extent& extent, double A, double shorelineX, double berm,
                                         double beachSlope) {
    DeanProfile p;
    p.A = A;
    p.shorelineX = shorelineX;
    p.bermHeight = berm;
    p.beachSlope = beachSlope;
    return makeDeanProfile(extent, p);
}

std::unique_ptr<Terrain> makeBarTrough(const Extent& extent, const BarTrough& p) {
    constexpr std::string_view what = "bar_trough";
    checkExtent(what, extent);
    checkDean(what, p.dean);
    requirePositive(what, "bar_crest_m", p.barCrestDistance);
    requirePositive(what, "bar_height_m", p.barHeight);
    requirePositive(what, "bar_width_m", p.barWidth);
    requirePositive(what, "trough_m", p.troughDistance);
    require(p.troughDistance < p.barCrestDistance, what, "trough_m", p.troughDistance,
            fmt::format("< bar_crest_m = {} m (the trough lies landward of the bar)", p.barCrestDistance));
    requireNonNegative(what, "trough_depth_m", p.troughDepth);
    requirePositive(what, "trough_width_m", p.troughWidth);
    requireNonNegative(what, "crescent_amplitude_m", p.crescentAmplitude);
    require(p.crescentAmplitude < p.troughDistance, what, "crescent_amplitude_m", p.crescentAmplitude,
            fmt::format("< trough_m = {} m (the meander may not reach the shoreline)", p.troughDistance));
    requirePositive(what, "crescent_wavelength_m", p.crescentWavelength);

    auto t = std::make_unique<BarTroughTerrain>(extent, p);
    // The bar must stay submerged: sample d over (0, crest + amplitude + 6 sigma] at sigma/20 and the
    // crescent phase at 64 points (the perturbation depends on y only through the phase).
    const double sigma = std::min(p.barWidth, p.troughWidth);
    const double dMax = p.barCrestDistance + p.crescentAmplitude + 6 * p.barWidth;
    const double step = std::min(sigma / 20, dMax / 2000);
    const int phases = p.crescentAmplitude > 0 ? 64 : 1;
    for (int k = 0; k < phases; ++k) {
        const double y = extent.y0 + p.crescentWavelength * double(k) / phases;
        for (double d = step; d <= dMax; d += step) {
            const double z = deanElevation(p.dean, d) + t->perturbation(d, y);
            if (z >= 0)
                throw InputError(fmt::format(
                    "bar_trough: the bar breaks the surface (z = {:.3f} m at {:.2f} m offshore); lower bar_height_m "
                    "({} m) or move bar_crest_m ({} m) into deeper water", z, d, p.barHeight,
                    p.barCrestDistance));
        }
    }
    return t;
}

}  // namespace littoral::bathymetry
