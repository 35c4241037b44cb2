// The column solver's isotropic Cox-Munk surface (column/rough_surface.h): the energy its
// operators conserve, the flat surface it tends to as the slopes vanish, and the directly
// transmitted sun against a slope quadrature written here (a Cartesian grid of slopes, its own
// Fresnel and Snell), not the solver's (polar midpoint rule).
#include <gtest/gtest.h>

#include <cmath>

#include "column/column_solver.h"
#include "column/rough_surface.h"
#include "core/units.h"

using namespace littoral;
using namespace littoral::column;

namespace {

constexpr double kN = 1.34;
constexpr double kMss723 = 0.003 + 0.00512 * 7.23;  // Cox and Munk's isotropic clean-sea fit, U = 7.23 m/s

// Fresnel reflectance of unpolarised light, incidence angle i on the side of index n1 (angle form).
double fresnelAngles(double i, double n1, double n2) {
    const double s = n1 / n2 * std::sin(i);
    if (s >= 1) return 1.0;
    if (i < 1e-9) return std::pow((n1 - n2) / (n1 + n2), 2);
    const double t = std::asin(s);
    const double rs = std::sin(i - t) / std::sin(i + t), rp = std::tan(i - t) / std::tan(i + t);
    return 0.5 * (rs * rs + rp * rp);
}

// Directly transmitted solar irradiance at depth z in non-scattering water of attenuation c, per unit
// irradiance normal to the beam: E0 cos(theta) sum over slopes of the intercepted fraction x (1 - F)
// x exp(-c z / mu_t), the fractions renormalised over the facets that face the sun (the model of
// rough_surface.h). Trapezoid rule on [-8 sigma, 8 sigma]^2 in (zx, zy), `n` points per axis.
double directTransmitted(double theta, double s2, double c, double z, int n) {
    const double sig = std::sqrt(s2), h = 16 * sig / (n - 1);
    const double dx = std::sin(theta), dz = -std::cos(theta);
    double sum = 0, norm = 0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double zx = -8 * sig + i * h, zy = -8 * sig + j * h;
            const double wt = (i == 0 || i == n - 1 ? 0.5 : 1.0) * (j == 0 || j == n - 1 ? 0.5 : 1.0);
            const double p = std::exp(-(zx * zx + zy * zy) / s2) / (kPi * s2);
            const double len = std::sqrt(1 + zx * zx + zy * zy), nx = -zx / len, ny = -zy / len, nz = 1 / len;
            const double cosI = -(dx * nx + dz * nz);
            if (cosI <= 0) continue;
            const double w = wt * p * cosI / (std::abs(dz) * nz);
            norm += w;
            const double eta = 1 / kN, ct = std::sqrt(1 - eta * eta * (1 - cosI * cosI));
            double tz = eta * dz + (eta * cosI - ct) * nz;
            tz = -std::abs(tz);  // a ray refracted upward would meet the surface again: mirrored
            (void)ny;
            sum += w * (1 - fresnelAngles(std::acos(std::min(1.0, cosI)), 1.0, kN)) * std::exp(-c * z / -tz);
        }
    return std::cos(theta) * sum / norm;
}

ColumnBand clearWater(double a, double b, double sunZenithDeg, double mss) {
    ColumnBand col;
    col.layers.push_back({0.0, a, b, PhaseFunction::henyeyGreenstein(0.8)});
    col.waterIndex = kN;
    col.sunZenith = deg2rad(sunZenithDeg);
    col.sunIrradiance = 1.0;
    col.surfaceMeanSquareSlope = mss;
    return col;
}

}  // namespace

// Each ray meets one facet, which reflects r and transmits 1 - r: for every incident direction the
// reflectance and transmittance sum to 1 (no shadowing, nothing lost). The sum is over ~41000 facets
// of weights renormalised to 1, so the tolerance is rounding, 1e-12. The mode-0 reflection matrix
// (binned into the stream cells) must carry exactly the reflected flux of each column: also 1e-12.
TEST(ColumnRoughSurface, ReflectancePlusTransmittanceIsOne) {
    const std::vector<Facet> facets = slopeQuadrature(kMss723);
    for (double deg = 0; deg < 89; deg += 5) {
        const double th = deg2rad(deg);
        for (double sgn : {-1.0, 1.0}) {  // from the air (travelling down), from the water (up)
            const SurfaceScatter s = scatterAtSurface(facets, kN, std::sin(th), 0, sgn * std::cos(th));
            EXPECT_NEAR(s.reflectance + s.transmittance, 1.0, 1e-12) << deg << " deg, side " << sgn;
        }
    }
    const Streams st = Streams::snellSplit(8, kN);
    const RoughSurfaceOperators op = roughSurfaceOperators(st, kN, kMss723, 1);
    for (int j = 0; j + 1 < st.size(); ++j) {
        double flux = 0;
        for (int i = 0; i + 1 < st.size(); ++i) flux += st.mu[i] * st.w[i] * op.reflectionFromBelow[0](i, j);
        EXPECT_NEAR(flux / (st.mu[j] * st.w[j]), op.reflectanceFromBelow[j], 1e-12) << "stream " << j;
    }
}

// As the mean-square slope goes to 0 the rough surface is the flat one. At s2 = 1e-10 the facets tilt
// by at most ~1e-4 rad: directions and Fresnel factors change by O(tilt^2) ~ 1e-8 on average
// (first-order changes cancel between opposite tilts), no reflected ray changes stream cell (the
// nodes lie > 1e-3 from the cell edges), so every quantity agrees with the flat solution to ~1e-8;
// asserted to 1e-6 relative.
TEST(ColumnRoughSurface, VanishingSlopesGiveTheFlatSurface) {
    for (double zenith : {30.0, 80.0}) {
        ColumnBand flat = clearWater(0.2, 0.8, zenith, 0.0);
        flat.skyRadiance = 0.1;
        flat.bottomDepth = 10.0;
        flat.bottomReflectance = 0.3;
        ColumnBand rough = flat;
        rough.surfaceMeanSquareSlope = 1e-10;
        const std::vector<double> z = {0.0, 1.0, 5.0, 10.0};
        const ColumnResult a = solveColumn(flat, z), b = solveColumn(rough, z);
        for (size_t k = 0; k < z.size(); ++k) {
            const DepthResult &f = a.depths[k], &r = b.depths[k];
            for (auto [x, y, what] : {std::tuple{f.Ed, r.Ed, "Ed"}, {f.Eu, r.Eu, "Eu"}, {f.Eod, r.Eod, "Eod"},
                                      {f.Eou, r.Eou, "Eou"}, {f.Lu, r.Lu, "Lu"}, {f.EdDirect, r.EdDirect, "Ed_direct"}})
                EXPECT_NEAR(y / x, 1.0, 1e-6) << what << " at " << z[k] << " m, sun " << zenith;
        }
        EXPECT_NEAR(b.LwNadir / a.LwNadir, 1.0, 1e-6) << zenith;
    }
}

// The directly transmitted sun just under the surface and below it, U = 7.23 m/s, against the
// Cartesian slope quadrature above. Tolerance: the two quadratures of the same integral differ by
// their discretisation errors; the Cartesian rule's own error is bounded by comparing 801 and 1601
// points per axis (`gridChange`), the solver's polar midpoint rule (160 x 256) has errors of the same
// kind (kinks where facets stop facing a low sun, and where Fresnel's r turns up), so the bound is
// 2 x 10^-4 + 10 x gridChange. The sub-beams (24 bins in the refracted angle, each keeping its mean
// 1/mu) add 1/2 (c z)^2 Var(1/mu) within a bin < 1e-5 at c z = 2.
TEST(ColumnRoughSurface, DirectTransmissionMatchesAnIndependentSlopeQuadrature) {
    const double c = 0.2;
    for (double zenith : {30.0, 80.0}) {
        const ColumnResult r = solveColumn(clearWater(c, 0.0, zenith, kMss723), {0.0, 1.0, 5.0, 10.0});
        for (const DepthResult& d : r.depths) {
            const double fine = directTransmitted(deg2rad(zenith), kMss723, c, d.depth, 1601);
            const double gridChange = std::abs(directTransmitted(deg2rad(zenith), kMss723, c, d.depth, 801) / fine - 1);
            EXPECT_NEAR(d.EdDirect / fine, 1.0, 2e-4 + 10 * gridChange) << zenith << " deg, z " << d.depth;
            EXPECT_NEAR(d.Ed, d.EdDirect, 1e-14);  // no scattering: all of Ed is direct
        }
    }
}
