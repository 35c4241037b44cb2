// Geometry against statistics (issue 10): a large facetized surface whose facet slopes follow Cox
// and Munk (the `cox-munk` wave model, surfaces/) reflects, on average, what the microfacet model
// of the rough interface (render/rough_dielectric.h, G = 1) predicts for the same slope variances.
//
// Facets: a collimated sun from direction i lights facet f (area A_f, unit normal n_f) with
// E max(0, i.n_f) A_f and it reflects r_f(i.n_f) of that (Eq. 4.2); per unit horizontal area
// (A_f n_fz summed) and unit incident flux E cos(theta_s):
//   R_geom = Sum_f w_f g(n_f) / Sum_f w_f,   w_f = A_f n_fz,   g(n) = max(0, i.n) r_f(i.n) / (n_z cos theta_s).
// Model: the same g averaged over the Gaussian slope density p_s with the mesh's measured upwind and
// crosswind mean-square slopes, which is the reflection albedo of the microfacet BxDF with G = 1
// (Int f_r cos = Int D(m) max(0, i.m) F dm / cos theta_s, and D(m) m_z dm = p_s dzx dzy; the white
// furnace test of tests/render/rough_dielectric_test.cpp checks the BxDF against that quadrature).
// Shadowing and second reflections between facets, which the model leaves out, are left out of
// the facet sum too; what is compared is the facets' slope distribution against the Gaussian.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/units.h"
#include "surfaces/wave_surface.h"
#include "tests/support/glint.h"

using namespace littoral;
namespace glint = littoral::testing_support::glint;

// Tolerance: the facets are one realization of a Gaussian field, so their mean of g scatters about
// the Gaussian expectation with a standard error of about sd(g) / sqrt(N_eff), N_eff = A / (pi L_u L_c)
// independent patches of the field's correlation lengths (docs/waves.md, cox-munk); measured
// variances remove the part of that scatter carried by the slope variances, which leaves the
// bound conservative. Asserted at 4 such standard errors, plus 1e-4 relative for the midpoint rule.
TEST(RoughGeometryStatistics, FacetizedCoxMunkSurfaceReflectsLikeTheMicrofacetModel) {
    surfaces::WaveParams p;
    p.model = surfaces::WaveModel::CoxMunk;
    p.windSpeed = 6.0;
    p.windDirection = 0.0;  // toward +x: x is the upwind axis
    p.sea = CoxMunkSea::Clean;
    p.sizeX = p.sizeY = 100.0;
    p.spacing = 0.25;
    p.triangles = 0;
    p.seed = 500;
    const surfaces::WaveSurface ws = surfaces::generateWaveSurface(p);
    const TriMesh& m = ws.mesh;
    const glint::SlopeVariances v{ws.actual.mssUpwind, ws.actual.mssCrosswind};
    // Correlation lengths of the cox-munk field: sqrt(2) h / sigma along and across the wind.
    const double h = 0.016 * p.windSpeed * p.windSpeed / std::sqrt(8.0);
    const double Lu = std::sqrt(2.0) * h / std::sqrt(v.upwind), Lc = std::sqrt(2.0) * h / std::sqrt(v.crosswind);
    const double nEff = p.sizeX * p.sizeY / (glint::kPi * Lu * Lc);
    for (double zenithDeg : {0.0, 30.0, 60.0})
        for (double azimuthDeg : {0.0, 90.0}) {
            const double th = deg2rad(zenithDeg), ph = deg2rad(azimuthDeg);
            const Vec3 i{std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)};
            auto g = [&](const Vec3& n) {
                const double c = dot(i, n);
                return c > 0 ? c * glint::fresnelSinTan(c, 1.0, 1.34) / (n.z * i.z) : 0.0;
            };
            double sw = 0, sg = 0, sg2 = 0;
            for (size_t f = 0; f < m.triangles.size(); ++f) {
                const Vec3 an = m.faceNormalArea(f);  // 2 A_f n_f
                const double area2 = length(an);
                const Vec3 n = an / area2;
                const double w = area2 * n.z, gv = g(n);
                sw += w;
                sg += w * gv;
                sg2 += w * gv * gv;
            }
            const double Rgeom = sg / sw, sd = std::sqrt(std::max(0.0, sg2 / sw - Rgeom * Rgeom));
            // Model: midpoint rule over +-8 standard deviations of the Gaussian slopes.
            const double su = std::sqrt(v.upwind), sc = std::sqrt(v.crosswind);
            const int q = 600;
            double Rmodel = 0;
            for (int a = 0; a < q; ++a)
                for (int b = 0; b < q; ++b) {
                    const double zx = (-8 + 16 * (a + 0.5) / q) * su, zy = (-8 + 16 * (b + 0.5) / q) * sc;
                    const double norm = std::sqrt(1 + zx * zx + zy * zy);
                    Rmodel += glint::slopePdf(v, zx, zy) * g(Vec3{-zx / norm, -zy / norm, 1 / norm}) * (16 * su / q) *
                              (16 * sc / q);
                }
            const double tol = 4 * sd / std::sqrt(nEff) + 1e-4 * Rmodel;
            EXPECT_NEAR(Rgeom, Rmodel, tol) << "sun zenith " << zenithDeg << " azimuth " << azimuthDeg;
            std::printf("[ geometry vs statistics ] sun %2.0f deg, azimuth %2.0f: facets %.6f, microfacet model %.6f "
                        "(difference %+.2f %%, tolerance %.2f %%)\n",
                        zenithDeg, azimuthDeg, Rgeom, Rmodel, 100 * (Rgeom / Rmodel - 1), 100 * tol / Rmodel);
        }
}
