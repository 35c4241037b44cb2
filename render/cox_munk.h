#pragma once
// The Cox-Munk slope distribution of a wind-roughened sea and the microfacet quantities derived
// from it: the normal distribution D, its sampling, and Smith masking.
//
// Frame. The local surface frame of render/bxdf.h: +z the macroscopic normal (out of the water),
// x and y tangent. A facet with slopes (zx, zy) = grad z has unit normal
//   m = (-zx, -zy, 1) / sqrt(1 + zx^2 + zy^2)                  (digest Eqs. 5.5-5.6)
// so zx = -mx/mz, zy = -my/mz and the tilt beta has cos(beta) = mz.
// The wind azimuth phi_w is the angle from local +x to the direction the wind blows TOWARD
// (counter-clockwise about +z), the convention of the Scene IR's Material::windAzimuth. A caller
// whose frame's x axis is the downwind direction passes 0 (Frame::fromNormalAndTangent).
// Slope components along the wind axes:
//   z_u = -grad z . e_down   (upwind: rate of rise toward upwind), e_down = (cos phi_w, sin phi_w)
//   z_c =  grad z . e_cross  (crosswind),                           e_cross = (-sin phi_w, cos phi_w)
//
// Slope density (Cox and Munk 1954; digest section 1.2), per unit slope area dzx dzy:
//   p_s = 1/(2 pi sigma_u sigma_c) exp(-(xi^2 + eta^2)/2) * P(xi, eta) / Z,
//   eta = z_u / sigma_u, xi = z_c / sigma_c,
// with P = 1 and Z = 1 for the Gaussian (the dissertation's model, the default), or with the
// Gram-Charlier series of Cox & Munk (1954) when enabled:
//   P = 1 - c21/2 (xi^2 - 1) eta - c03/6 (eta^3 - 3 eta) + c40/24 (xi^4 - 6 xi^2 + 3)
//         + c22/4 (xi^2 - 1)(eta^2 - 1) + c04/24 (eta^4 - 6 eta^2 + 3).
// The c21 and c03 terms are odd in eta; the skewness E[eta^3] = -c03 is positive for U > 1.2 m/s:
// a long tail of large positive z_u, i.e. of steep facets facing downwind (the steep leeward faces
// of wind waves). That reading fixes our sign of z_u; it follows from the physics of wind waves,
// not from a figure of the 1954 paper, which we could not consult.
// Negativity: above about 9 m/s the series dips below zero in the tails (near eta = -4.5, xi = 0
// at 10 m/s). We use max(P, 0) and divide by Z = Int phi max(P, 0), computed once per distribution
// by quadrature. Z - 1 is the clipped mass: 0 up to about 9 m/s, 8e-6 at 10 m/s, 4e-4 at 14 m/s.
// So p_s is a density: >= 0, integral 1.
//
// Microfacet normal distribution (digest section 1.2):
//   D(m) = p_s(zx(m), zy(m)) / cos^4(theta_m),  m_z > 0,
// normalised so that Int D(m) cos(theta_m) d omega_m = 1, because d omega_m = cos^3 dzx dzy.
// For the Gaussian this is Beckmann's anisotropic distribution with alpha = sqrt(2) sigma.
//
// Sampling (a triple, slopes and normals alike): sampleSlope draws (z_u, z_c) from the Gaussian
// part by the Box-Muller map u -> (r, psi), r = sqrt(-2 ln(1 - u.x)), psi = 2 pi u.y; invertSlope
// is its exact inverse; the density of what it draws is gaussianSlopePdf (per slope area) or
// pdfNormal = D_gauss(m) cos(theta_m) (per solid angle of m). With Gram-Charlier terms on, the
// sampler still draws the Gaussian part: its pdf is the Gaussian one, and the BxDF carries the
// ratio D / D_gauss in its weights (importance sampling, unbiased; no rejection loop).
//
// Smith masking (Smith 1967; Walter et al. 2007, eqs. 25-27 with the exact Beckmann Lambda):
//   G1(w, m) = chi+((w.m)/(w.n)) / (1 + Lambda(a)),  a = 1 / (sqrt(2) sigma(phi) |tan theta|),
//   Lambda(a) = (erf(a) - 1)/2 + exp(-a^2) / (2 a sqrt(pi)),
// where sigma(phi)^2 = sigma_u^2 cos^2(phi - phi_w) + sigma_c^2 sin^2(phi - phi_w) is the variance
// of the slope component along w's azimuth phi. For the Gaussian it satisfies exactly
//   Int G1(w, m) max(0, w.m) D(m) d omega_m = |w.n|    (projected area of the visible facets),
// which is what makes the interface conserve energy (render/rough_dielectric.h). With Gram-Charlier
// terms the Gaussian Lambda is used as an approximation.
//
// Build one distribution per material, not per hit: with Gram-Charlier terms the constructor runs
// the quadrature for Z (some 20 ms).
#include "core/cox_munk_fit.h"
#include "core/error.h"
#include "core/vec.h"

namespace littoral::render {

struct CoxMunkParams {
    double windSpeed = 5.0;    // m/s at 12.5 m
    double windAzimuth = 0.0;  // radians from local +x to the direction the wind blows toward
    CoxMunkSea sea = CoxMunkSea::Clean;
    bool gramCharlier = false;  // clean sea only
    CoxMunkSlopes slopes = CoxMunkSlopes::Anisotropic;  // isotropic: clean sea, no Gram-Charlier
};

class CoxMunkDistribution {
public:
    // Throws InputError (at `where`, naming `key` for the wind) when the wind is outside
    // CoxMunkLimits or Gram-Charlier terms are asked for with a sea other than clean.
    explicit CoxMunkDistribution(const CoxMunkParams& p, const SourceLoc& where = {},
                                 std::string_view windKey = "wind_speed");
    // A Gaussian of given slope variances (> 0), e.g. measured on a facetized surface.
    static CoxMunkDistribution fromVariances(double varUpwind, double varCrosswind, double windAzimuth);

    double varianceUpwind() const { return varU_; }
    double varianceCrosswind() const { return varC_; }
    double windAzimuth() const { return phiW_; }
    bool gramCharlier() const { return gc_; }
    // Z: the Gram-Charlier series' integral after clipping at zero (1 without the series).
    double gramCharlierNormalization() const { return z_; }

    // Slopes in the local frame <-> along/across the wind.
    Vec2 toWindSlopes(const Vec2& gradZ) const;    // (zx, zy) -> (z_u, z_c)
    Vec2 fromWindSlopes(const Vec2& windZ) const;  // (z_u, z_c) -> (zx, zy)

    // p_s(zx, zy), per unit slope area (includes the Gram-Charlier factor when enabled).
    double slopePdf(const Vec2& gradZ) const;
    // The Gaussian part alone: the density sampleSlope draws from.
    double gaussianSlopePdf(const Vec2& gradZ) const;
    Vec2 sampleSlope(const Vec2& u) const;     // -> (zx, zy); u in [0, 1)^2
    Vec2 invertSlope(const Vec2& gradZ) const;  // -> u

    // D(m), sr^-1 (0 for m_z <= 0), and its Gaussian part.
    double D(const Vec3& m) const;
    double gaussianD(const Vec3& m) const;
    // A microfacet normal (m_z > 0) with density pdfNormal(m) = gaussianD(m) m_z per solid angle.
    Vec3 sampleNormal(const Vec2& u) const;
    double pdfNormal(const Vec3& m) const { return gaussianD(m) * m.z; }
    Vec2 invertNormal(const Vec3& m) const;

    // Smith: Lambda(w) (0 at normal incidence, +inf at grazing) and G1(w, m); w on either side of
    // the surface (the slopes seen from below are the same height field upside down).
    double lambda(const Vec3& w) const;
    double G1(const Vec3& w, const Vec3& m) const;
    // Variance of the slope component along the horizontal direction at azimuth phi (radians).
    double varianceAlong(double phi) const;

private:
    CoxMunkDistribution() = default;
    double gcFactor(double xi, double eta) const;  // max(P, 0) / Z
    double varU_ = 0, varC_ = 0, sigU_ = 0, sigC_ = 0, phiW_ = 0, cosW_ = 1, sinW_ = 0;
    bool gc_ = false;
    GramCharlierCoefficients c_{};
    double z_ = 1.0;
};

// Smith's Lambda for a Gaussian slope distribution in terms of a = cot(theta) / (sqrt(2) sigma).
double beckmannLambda(double a);

}  // namespace littoral::render
