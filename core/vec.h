#pragma once
// Small fixed-size vector types used everywhere: points, directions, normals (metres, unitless).
// Plain aggregates so they can sit in hot loops and be copied freely.
#include <cmath>
#include <ostream>

namespace littoral {

struct Vec2 {
    double x = 0, y = 0;
    constexpr Vec2() = default;
    constexpr Vec2(double x_, double y_) : x(x_), y(y_) {}
    constexpr Vec2 operator+(const Vec2& b) const { return {x + b.x, y + b.y}; }
    constexpr Vec2 operator-(const Vec2& b) const { return {x - b.x, y - b.y}; }
    constexpr Vec2 operator*(double s) const { return {x * s, y * s}; }
    constexpr bool operator==(const Vec2&) const = default;
};

struct Vec3 {
    double x = 0, y = 0, z = 0;
    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3 operator+(const Vec3& b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr Vec3 operator-(const Vec3& b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    Vec3& operator+=(const Vec3& b) { x += b.x; y += b.y; z += b.z; return *this; }
    Vec3& operator-=(const Vec3& b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
    Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3&) const = default;
};

// Points and normals share the representation; the names document intent at interfaces.
using Point3 = Vec3;
using Normal3 = Vec3;

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double absDot(const Vec3& a, const Vec3& b) { return std::abs(dot(a, b)); }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr double lengthSquared(const Vec3& a) { return dot(a, a); }
inline double length(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline double distance(const Vec3& a, const Vec3& b) { return length(a - b); }
inline Vec3 normalize(const Vec3& a) { return a / length(a); }
constexpr Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
// std::fmin and std::fmax's rule (a NaN argument loses to the other) inline: GCC calls libm's for
// them, and bounding boxes are grown per photon (the photon pass spent 3-4 % of its time in the calls).
inline double fminInline(double a, double b) { return b < a || a != a ? b : a; }
inline double fmaxInline(double a, double b) { return b > a || a != a ? b : a; }
inline Vec3 vmin(const Vec3& a, const Vec3& b) { return {fminInline(a.x, b.x), fminInline(a.y, b.y), fminInline(a.z, b.z)}; }
inline Vec3 vmax(const Vec3& a, const Vec3& b) { return {fmaxInline(a.x, b.x), fmaxInline(a.y, b.y), fmaxInline(a.z, b.z)}; }
inline bool isFinite(const Vec3& a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
// Flip n to lie in the hemisphere of v.
inline Vec3 faceForward(const Vec3& n, const Vec3& v) { return dot(n, v) < 0 ? -n : n; }

// Mirror reflection of incoming-pointing-away direction wo about normal n: both point away from the surface.
inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return -wo + 2 * dot(wo, n) * n; }

// Snell refraction (pbrt convention): wi points away from the surface on the incident side,
// n is on the same side as wi, eta = n_incident / n_transmitted. Returns false on total
// internal reflection; otherwise wt points away from the surface on the transmitted side.
inline bool refract(const Vec3& wi, const Vec3& n, double eta, Vec3* wt) {
    const double cosI = dot(n, wi);
    const double sin2I = fmaxInline(0.0, 1.0 - cosI * cosI);
    const double sin2T = eta * eta * sin2I;
    if (sin2T >= 1.0) return false;
    const double cosT = std::sqrt(1.0 - sin2T);
    *wt = eta * -wi + (eta * cosI - cosT) * n;
    return true;
}

inline std::ostream& operator<<(std::ostream& os, const Vec3& v) {
    return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}

}  // namespace littoral
