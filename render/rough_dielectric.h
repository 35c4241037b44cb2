#pragma once
// The wind-roughened air-water interface: a rough dielectric BxDF whose microfacets are the
// Cox-Munk slopes of render/cox_munk.h (Walter, Marschner, Li and Torrance 2007, "Microfacet
// models for refraction through rough surfaces"; the dissertation's "sub-pixel capillary waves",
// spec/seed-ch05-10.md sections 1.4-1.7).
//
// Conventions are those of render/bxdf.h: local frame with +z the outward macroscopic normal (the
// side of index nOut, air for the sea surface); wo and wi point away from the surface; f in sr^-1;
// pdf per unit solid angle of wi; TransportMode::Radiance for camera paths, Importance for photons.
// Unlike DielectricBxDF this BxDF is not delta: f and pdf are real functions and sample() returns
// flags kGlossy | kReflection or kGlossy | kTransmission.
//
// Indices: eta_o is the index on wo's side, eta_i on wi's side (both nOut or nIn).
// Half vectors, oriented so that h.z > 0 (the microfacet normals of a height field point up):
//   reflection    h_r ~ wo + wi
//   transmission  h_t ~ -(eta_o wo + eta_i wi)                              (Walter eq. 16)
// A pair contributes only if each direction is on its own side of the facet as well as of the
// macrosurface: (w . h) w.z > 0 for w = wo and wi. F = r_f(|wo.h|) (Eq. 4.2; the same value as
// r_f(|wi.h|) for a transmission pair, Snell being symmetric).
//
// Reflection (Walter eq. 20; the dissertation's Eq. 5.4 is f_r cos(theta_i) with G = 1):
//   f_r = F D(h_r) G / (4 |wo.z| |wi.z|)
// Transmission (Walter eq. 21, NOT the printed Eq. 5.20, which transmits about 5% of the flux
// instead of about 98%; digest section 1.6), in Radiance mode:
//   f_t = |wi.h| |wo.h| / (|wi.z| |wo.z|) * eta_o^2 (1 - F) G D(h_t) / (eta_o (wo.h) + eta_i (wi.h))^2
// The eta_o^2 carries the n^2 law of radiance (Sec. 4.0); in Importance mode it is eta_i^2, which
// makes f_importance(wo, wi) = f_radiance(wi, wo), the adjoint BSDF (Veach 1997, ch. 5).
//
// Shadowing-masking term G (MicrofacetShadowing, core/cox_munk_fit.h):
//   None            G = 1: Eq. 5.4 and the dissertation's analytic predictions (this struct's
//                   default, for those tests; it gains energy toward grazing incidence, below).
//   SmithLight      G = G1(direction the light arrives from): G1(wi) in Radiance mode, G1(wo) in
//                   Importance mode; the adjoint relation above holds for it. The scene's default
//                   (core/scene_ir.h), and the column solver's surface (column/rough_surface.h).
//   SmithSeparable  G = G1(wo) G1(wi) (Walter eq. 23): reciprocal, loses the light that a second
//                   bounce between facets would return.
// Energy. Light of unit flux arriving from direction l falls on facets m with projected density
// G1(l, m) max(0, l.m) D(m) / |l.z|; each facet reflects F and transmits 1 - F. Integrating f |cos|
// over the outgoing hemisphere and changing variables to h (Jacobians 1/(4|wo.h|) for reflection,
// eta_i^2 |wi.h| / (eta_o wo.h + eta_i wi.h)^2 for transmission) gives, for the BxDF above,
//   Int f(l, w) |w.z| dw = (1/|l.z|) Int_{visible h} [F + (1 - F)] G D |l.h| dh
//                        - (flux scattered by a facet into the wrong hemisphere, which a
//                           single-scattering model cannot represent).
// With G = G1(l) the first term is exactly 1 (Smith's identity in cox_munk.h), so SmithLight
// conserves the flux up to that wrong-hemisphere loss. Measured by quadrature (tests): below 2e-4
// up to 30 degrees incidence from the air and 2e-3 from the water, for winds up to 14 m/s; 0.3 %
// (6 m/s) to 1.2 % (14 m/s) at 60 degrees from the air; 1 to 6 % at grazing incidence and beyond
// the critical angle. None gains energy (the first term exceeds 1: R + T = 1.42, 2.05 and 2.80 at
// 88 degrees from the air for 2, 6 and 14 m/s); SmithSeparable loses some (R + T = 0.947 to
// 0.968 at 88 degrees). The tests assert each against an independent quadrature over the slopes.
//
// Sampling: a microfacet normal from the Gaussian slope density (CoxMunkDistribution::
// sampleNormal, pdf D_gauss(h) h.z), then reflection with probability F and refraction with 1 - F
// (reflection only under total internal reflection); a normal facing away from wo, or a
// direction that ends on the wrong side of the macrosurface, fails (std::nullopt). pdf(wo, wi) is
// the density of the directions this produces, so it integrates to the success probability:
//   reflection    pdf = D_gauss(h) h.z F / (4 |wo.h|)
//   transmission  pdf = D_gauss(h) h.z (1 - F) eta_i^2 |wi.h| / (eta_o (wo.h) + eta_i (wi.h))^2
// It does not depend on the transport mode. For next-event estimation with multiple importance
// sampling (sun disc vs BSDF sampling) evaluate() returns f and pdf of a given pair in one call.
//
// Build once per material (the distribution may hold a quadrature result) and copy it per hit.
#include <cstdint>
#include <optional>

#include "core/names.h"
#include "core/vec.h"
#include "render/bxdf_types.h"
#include "render/cox_munk.h"

namespace littoral::render {

struct RoughDielectricBxDF {
    // nOut on the +z side, nIn below; they must differ by more than 1e-6 (InputError otherwise:
    // a rough interface between equal indices would refract every ray straight through).
    RoughDielectricBxDF(double nOut, double nIn, CoxMunkDistribution slopes,
                        MicrofacetShadowing shadowing = MicrofacetShadowing::None);

    double nOut = 1.0, nIn = 1.34;
    CoxMunkDistribution slopes;
    MicrofacetShadowing shadowing = MicrofacetShadowing::None;

    uint8_t flags() const { return kReflection | kTransmission | kGlossy; }
    double f(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
    double pdf(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;
    // uc chooses reflection (uc < F) or refraction; u chooses the microfacet normal.
    std::optional<BSDFSample> sample(const Vec3& wo, double uc, const Vec2& u,
                                     TransportMode mode = TransportMode::Radiance) const;

    // The transmission lobe alone: a microfacet normal h from the Gaussian slope density and the
    // direction refracted at it, whatever its Fresnel reflectance (nullopt if the normal faces away
    // from wo, under total internal reflection, or if the refracted direction stays on wo's side).
    // For estimators that want only transmitted light (the sun seen from under a rough surface:
    // choosing the lobe by F there would only add the noise of a coin toss). Its density per solid
    // angle of wi is the transmission pdf above without the lobe choice:
    //   pdfTransmission = D_gauss(h) h.z eta_i^2 |wi.h| / (eta_o (wo.h) + eta_i (wi.h))^2
    // (0 for a pair that is not a transmission, or that total internal reflection forbids).
    std::optional<Vec3> sampleTransmission(const Vec3& wo, const Vec2& u) const;
    double pdfTransmission(const Vec3& wo, const Vec3& wi) const;

    // f and pdf of one pair, with the lobe it belongs to (flags 0 when f = pdf = 0).
    struct Evaluation {
        double f = 0, pdf = 0;
        uint8_t flags = 0;
        double etap = 1;  // eta_i / eta_o for transmission, else 1
    };
    Evaluation evaluate(const Vec3& wo, const Vec3& wi, TransportMode mode = TransportMode::Radiance) const;

    // The masking term of a (wo, wi, h) configuration under `shadowing` (1 for None).
    double G(const Vec3& wo, const Vec3& wi, const Vec3& h, TransportMode mode) const;
};

}  // namespace littoral::render
