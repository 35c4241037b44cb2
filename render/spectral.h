#pragma once
// Per-band values carried along a path: band-averaged spectral radiance (W m^-2 sr^-1 um^-1),
// reflectances, transmittances. A fixed-capacity inline array so the hot path never allocates;
// the integrator processes the render bands in groups of at most kMaxGroupBands (a group also
// shares one refractive index per medium, so that all its bands follow the same ray geometry).
#include <algorithm>
#include <array>
#include <cmath>

namespace littoral::render {

inline constexpr int kMaxGroupBands = 16;

struct Spec {
    int n = 0;  // bands in use
    std::array<double, kMaxGroupBands> v;  // only v[0, n) is meaningful (not zero-filled: hot path)

    Spec() = default;
    explicit Spec(int count, double x = 0.0) : n(count) {
        for (int i = 0; i < n; ++i) v[i] = x;
    }
    // Copies move only the n bands in use: a whole-array copy (136 bytes) per return and per
    // temporary was the renderer's largest single cost (bench_render), much of it store-forwarding
    // stalls on the partly written array. (render/ is compiled so that these loops stay loops: a
    // memset / memmove call costs more than the one to four bands a group usually has.)
    Spec(const Spec& o) : n(o.n) {
        for (int i = 0; i < n; ++i) v[i] = o.v[i];
    }
    Spec& operator=(const Spec& o) {
        n = o.n;
        for (int i = 0; i < n; ++i) v[i] = o.v[i];
        return *this;
    }
    double& operator[](int i) { return v[i]; }
    double operator[](int i) const { return v[i]; }

    Spec& operator+=(const Spec& o) { for (int i = 0; i < n; ++i) v[i] += o.v[i]; return *this; }
    Spec& operator-=(const Spec& o) { for (int i = 0; i < n; ++i) v[i] -= o.v[i]; return *this; }
    Spec& operator*=(const Spec& o) { for (int i = 0; i < n; ++i) v[i] *= o.v[i]; return *this; }
    Spec& operator*=(double s) { for (int i = 0; i < n; ++i) v[i] *= s; return *this; }
    Spec operator+(const Spec& o) const { Spec r = *this; r += o; return r; }
    Spec operator-(const Spec& o) const { Spec r = *this; r -= o; return r; }
    Spec operator*(const Spec& o) const { Spec r = *this; r *= o; return r; }
    Spec operator*(double s) const { Spec r = *this; r *= s; return r; }
    bool isBlack() const { for (int i = 0; i < n; ++i) if (v[i] != 0.0) return false; return true; }
    double maxValue() const { double m = 0; for (int i = 0; i < n; ++i) m = std::max(m, v[i]); return m; }
};

// Beer–Lambert transmittance exp(-c s) per band (Eq. 2.4), c in m^-1, s in m.
inline Spec beerLambert(const Spec& c, double s) {
    Spec t(c.n);
    for (int i = 0; i < c.n; ++i) t.v[i] = c.v[i] == 0.0 ? 1.0 : std::exp(-c.v[i] * s);
    return t;
}

}  // namespace littoral::render
