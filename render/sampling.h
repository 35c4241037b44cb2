#pragma once
// Sampling routines, each as a triple: sampleX(u) -> direction, pdfX(direction), and where it
// exists invertX(direction) -> u. Directions are in a local frame with the normal along +z.
// Pdfs are per unit solid angle (sr^-1).
#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "core/vec.h"

namespace littoral::render {

// Cosine-weighted hemisphere (Malley's method on the equal-area disc map): pdf = cos(theta)/pi.
// u.x = sin^2(theta) (the fraction of projected solid angle below theta), u.y = phi / 2 pi, so
// equal cells in u are equal-projected-solid-angle sky quads.
inline Vec3 sampleCosineHemisphere(double u1, double u2) {
    const double s = std::sqrt(u1);
    const CosSin phi = cosSinTurns(u2);
    return {s * phi.c, s * phi.s, std::sqrt(std::max(0.0, 1.0 - u1))};
}
inline double pdfCosineHemisphere(const Vec3& w) { return w.z > 0 ? w.z * kInvPi : 0.0; }
inline Vec2 invertCosineHemisphere(const Vec3& w) {
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2.0 * kPi;
    return {w.x * w.x + w.y * w.y, phi / (2.0 * kPi)};
}

// Uniform hemisphere: pdf = 1 / (2 pi); u.x = cos(theta), u.y = phi / 2 pi.
inline Vec3 sampleUniformHemisphere(double u1, double u2) {
    const double z = u1;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const CosSin phi = cosSinTurns(u2);
    return {r * phi.c, r * phi.s, z};
}
inline double pdfUniformHemisphere(const Vec3& w) { return w.z > 0 ? 1.0 / (2.0 * kPi) : 0.0; }
inline Vec2 invertUniformHemisphere(const Vec3& w) {
    double phi = std::atan2(w.y, w.x);
    if (phi < 0) phi += 2.0 * kPi;
    return {w.z, phi / (2.0 * kPi)};
}

// Uniform cone of half-angle alpha around +z: pdf = 1 / (2 pi (1 - cos alpha)).
inline Vec3 sampleUniformCone(double u1, double u2, double cosAlpha) {
    const double z = 1.0 - u1 * (1.0 - cosAlpha);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const CosSin phi = cosSinTurns(u2);
    return {r * phi.c, r * phi.s, z};
}
inline double pdfUniformCone(const Vec3& w, double cosAlpha) {
    return w.z >= cosAlpha ? 1.0 / (2.0 * kPi * (1.0 - cosAlpha)) : 0.0;
}

// A stratified layout of n samples over the unit square: a mu x phi grid of equal cells
// (mu = max(1, floor(sqrt(n / 2))) rows in u.x, phi = floor(n / mu) columns in u.y, so cells are
// about twice as wide in azimuth as in sin^2 theta, like DIRSIG's mu x phi sky quads), and any
// remainder n - mu*phi drawn unstratified over the whole square. Sample k's cell and its
// jitter (j1, j2) give the point.
struct StratifiedLayout {
    int n = 1, mu = 1, phi = 1;
    explicit StratifiedLayout(int count) : n(std::max(1, count)) {
        mu = std::max(1, static_cast<int>(std::floor(std::sqrt(n / 2.0))));
        phi = std::max(1, n / mu);
    }
    int cells() const { return mu * phi; }
    Vec2 point(int k, double j1, double j2) const {
        if (k >= cells()) return {j1, j2};
        const int i = k / phi, j = k % phi;
        return {(i + j1) / mu, (j + j2) / phi};
    }
};

}  // namespace littoral::render
