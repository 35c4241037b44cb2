#include "column/column_solver.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "column/legendre.h"
#include "column/rough_surface.h"
#include "column/slab.h"
#include "core/error.h"
#include "core/units.h"

namespace littoral::column {

double fresnelReflectance(double cosI, double n1, double n2) {
    cosI = std::clamp(cosI, 0.0, 1.0);
    const double sinT = n1 / n2 * std::sqrt(std::max(0.0, 1.0 - cosI * cosI));
    if (sinT >= 1.0) return 1.0;
    const double cosT = std::sqrt(1.0 - sinT * sinT);
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    const double rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

namespace {

// A layer after delta-M scaling (Wiscombe 1977): f = chi_L, the forward peak beyond the kept
// moments, is moved into the unscattered beam.
struct ScaledLayer {
    double cScaled = 0;  // (1 - omega f) c, m^-1
    double f = 0;
    ScaledOptics optics;  // omega' = omega (1 - f) / (1 - omega f), chi'_l = (chi_l - f) / (1 - f)
    const PhaseFunction* phase = nullptr;
};

ScaledLayer scaleLayer(const ColumnLayer& l, int order) {
    ScaledLayer s;
    s.phase = &l.phase;
    const double c = l.a + l.b;
    const double omega = c > 0 ? l.b / c : 0.0;
    std::vector<double> chi = l.b > 0 ? legendreMoments(l.phase, order + 1) : std::vector<double>(static_cast<size_t>(order + 1), 0.0);
    chi[0] = 1.0;
    s.f = l.b > 0 ? std::clamp(chi[static_cast<size_t>(order)], 0.0, 1.0 - 1e-12) : 0.0;
    s.cScaled = (1 - omega * s.f) * c;
    s.optics.omega = s.f < 1 && omega > 0 ? omega * (1 - s.f) / (1 - omega * s.f) : 0.0;
    s.optics.chi.resize(static_cast<size_t>(order));
    for (int i = 0; i < order; ++i) s.optics.chi[static_cast<size_t>(i)] = (chi[static_cast<size_t>(i)] - s.f) / (1 - s.f);
    return s;
}

// The planes of the computation: the surface, every requested depth, every layer top and the
// bottom; sublayer k lies between plane k and k + 1.
struct Grid {
    std::vector<double> z;       // m
    std::vector<double> tau;     // scaled optical depth at each plane
    std::vector<int> layer;      // layer of sublayer k
    std::vector<int> requested;  // plane index of each requested depth
    bool bottomPlane = false;    // the last plane is the bottom
};

Grid makeGrid(const ColumnBand& col, const std::vector<ScaledLayer>& layers, const std::vector<double>& depths) {
    Grid g;
    std::vector<double> z = depths;
    z.push_back(0.0);
    for (const auto& l : col.layers)
        if (!col.bottomDepth || l.top < *col.bottomDepth) z.push_back(l.top);
    if (col.bottomDepth) z.push_back(*col.bottomDepth);
    std::sort(z.begin(), z.end());
    for (double v : z)
        if (g.z.empty() || v > g.z.back() + 1e-9) g.z.push_back(v);
    g.tau.push_back(0.0);
    for (size_t k = 0; k + 1 < g.z.size(); ++k) {
        const int li = col.layerAt(0.5 * (g.z[k] + g.z[k + 1]));
        g.layer.push_back(li);
        g.tau.push_back(g.tau.back() + layers[static_cast<size_t>(li)].cScaled * (g.z[k + 1] - g.z[k]));
    }
    for (double d : depths) {
        size_t k = 0;
        while (k + 1 < g.z.size() && g.z[k] < d - 1e-9) ++k;
        g.requested.push_back(static_cast<int>(k));
    }
    g.bottomPlane = col.bottomDepth.has_value();
    return g;
}

struct ModeField {
    std::vector<std::vector<double>> down, up;  // diffuse radiance of the mode at each plane
};

struct Setup {
    const ColumnBand* col;
    Streams s;
    std::vector<ScaledLayer> layers;
    Grid grid;
    double mu0 = 1;  // the refracted beam's cosine through a flat surface
    // The solar beam in the water: one beam (flat surface) or the sub-beams of a rough one; each
    // with its cosine and its flux through a horizontal plane at 0-.
    std::vector<SubBeam> beams;
    std::optional<RoughSurfaceOperators> rough;
};

// Flux of one beam through the horizontal plane at every grid plane.
std::vector<double> beamAt(const Setup& st, const SubBeam& b) {
    std::vector<double> v;
    for (double t : st.grid.tau) v.push_back(b.flux * std::exp(-t / b.mu));
    return v;
}

// The surface seen from below in mode m: its reflection of upwelling radiance, and the sky
// radiance it lets in (n^2 law; mode 0 only).
void surfaceFromBelow(const Setup& st, int m, Matrix* r, std::vector<double>* sky) {
    const Streams& s = st.s;
    const int n = s.size();
    const double nw = st.col->waterIndex;
    sky->assign(static_cast<size_t>(n), 0.0);
    if (st.rough) {
        *r = st.rough->reflectionFromBelow[static_cast<size_t>(m)];
        if (m == 0)
            for (int i = 0; i < n; ++i) (*sky)[static_cast<size_t>(i)] = st.col->skyRadiance * st.rough->skyTransmission[static_cast<size_t>(i)];
        return;
    }
    // Flat: specular (mode-independent) reflection, total outside the Snell window.
    std::vector<double> rs(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        const double rf = fresnelReflectance(s.mu[static_cast<size_t>(i)], nw, 1.0);
        rs[static_cast<size_t>(i)] = rf;
        if (m == 0 && rf < 1.0) (*sky)[static_cast<size_t>(i)] = st.col->skyRadiance * nw * nw * (1.0 - rf);
    }
    *r = Matrix::diagonal(rs);
}

// The diffuse field of Fourier mode m at every plane, by adding (see docs/column.md): composites of
// everything above each plane (its reflectance for upwelling light, the downwelling radiance it
// sends with a black column below) from the top down, of everything below (reflectance, upwelling
// radiance per unit beam flux) from the bottom up, then the two joined at each plane.
// `beamIn`: the beam whose sources are included (its flux times its mode-m azimuth factor); the sky
// is included when `withSky`. The field is linear in both, so a rough surface's sub-beams are solved
// one at a time and summed.
ModeField solveMode(const Setup& st, int m, const SubBeam& beamIn, bool withSky) {
    const Streams& s = st.s;
    const int n = s.size();
    const Grid& g = st.grid;
    const size_t planes = g.z.size();
    const double mu0 = beamIn.mu;
    std::vector<double> beam = beamAt(st, beamIn);
    for (double& b : beam) b *= beamIn.modeFactor(m);
    std::map<std::pair<int, double>, SlabOperators> cache;
    auto slab = [&](size_t k) -> const SlabOperators& {
        const int li = g.layer[k];
        const double dz = g.z[k + 1] - g.z[k];
        auto it = cache.find({li, dz});
        if (it == cache.end())
            it = cache.emplace(std::make_pair(li, dz), slabOperators(s, st.layers[static_cast<size_t>(li)].optics, m, mu0,
                                                                      std::max(g.tau[k + 1] - g.tau[k], 1e-300))).first;
        return it->second;
    };
    std::vector<Matrix> above(planes);
    std::vector<std::vector<double>> dAbove(planes);
    surfaceFromBelow(st, m, &above[0], &dAbove[0]);
    if (!withSky) dAbove[0].assign(static_cast<size_t>(n), 0.0);
    const Matrix id = Matrix::identity(n);
    for (size_t k = 0; k + 1 < planes; ++k) {
        const SlabOperators& b = slab(k);
        const Matrix a = id - above[k] * b.R;
        const std::vector<double> x = solve(a, dAbove[k] + beam[k] * (above[k] * b.su));
        dAbove[k + 1] = b.T * x + beam[k] * b.sd;
        above[k + 1] = b.R + b.T * (solve(a, above[k] * b.T));
    }
    // Below the last plane: the Lambertian bottom (mode 0 only), or the semi-infinite last layer.
    std::vector<Matrix> below(planes);
    std::vector<std::vector<double>> uBelow(planes);
    if (g.bottomPlane) {
        below.back() = Matrix(n, n);
        uBelow.back().assign(static_cast<size_t>(n), m == 0 ? st.col->bottomReflectance * kInvPi : 0.0);
        if (m == 0)
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j)
                    below.back()(i, j) = 2.0 * st.col->bottomReflectance * s.w[static_cast<size_t>(j)] * s.mu[static_cast<size_t>(j)];
    } else {
        const int li = st.col->layerAt(g.z.back() + 1.0);
        const SlabOperators inf = slabOperators(s, st.layers[static_cast<size_t>(li)].optics, m, mu0,
                                                std::numeric_limits<double>::infinity());
        below.back() = inf.R;
        uBelow.back() = inf.su;
    }
    for (size_t k = planes - 1; k-- > 0;) {
        const SlabOperators& b = slab(k);
        const Matrix a = id - b.R * below[k + 1];
        const std::vector<double> x = solve(a, b.sd + b.beamT * (b.R * uBelow[k + 1]));
        const std::vector<double> y = below[k + 1] * x + b.beamT * uBelow[k + 1];
        uBelow[k] = b.su + b.T * y;
        below[k] = b.R + b.T * (below[k + 1] * solve(a, b.T));
    }
    ModeField f;
    for (size_t k = 0; k < planes; ++k) {
        const std::vector<double> down = solve(id - above[k] * below[k], dAbove[k] + beam[k] * (above[k] * uBelow[k]));
        f.up.push_back(beam[k] * uBelow[k] + below[k] * down);
        f.down.push_back(down);
    }
    return f;
}

}  // namespace

namespace {

// -expm1(-x d)/x = Int_0^d e^{-x s} ds for x >= 0.
double h(double x, double d) { return x * d < 1e-8 ? d : -std::expm1(-x * d) / x; }

// Nakajima and Tanaka (1988) TMS: the single-scattered radiance of the delta-M problem (truncated
// phase function p*, scaled albedo) is replaced by that of the exact phase function,
//   dI = Int (E_b0/mu0) e^{-tau'/mu0} [omega'/(1 - f) p(Theta) - omega' p*(Theta)] e^{-|tau' - tau_k|/|mu|} dtau'/|mu|
// along the line of sight within the water (scaled optical depths), layer by layer in closed form.
// `mu` signed (> 0 travelling down), cosTheta the scattering angle from the refracted beam.
double tmsCorrection(const Setup& st, const SubBeam& beam, size_t plane, double mu, double cosTheta) {
    const Grid& g = st.grid;
    const double tk = g.tau[plane], u = std::abs(mu), a0 = 1 / beam.mu;
    std::map<int, double> kappa;
    auto coefficient = [&](int li) {
        auto it = kappa.find(li);
        if (it != kappa.end()) return it->second;
        const ScaledLayer& l = st.layers[static_cast<size_t>(li)];
        double pStar = 0;
        const auto pl = normalizedAssociatedLegendre(0, static_cast<int>(l.optics.chi.size()) - 1, cosTheta);
        for (size_t i = 0; i < l.optics.chi.size(); ++i) pStar += (2.0 * i + 1) * l.optics.chi[i] * pl[i];
        pStar /= 4 * kPi;
        const double c = l.optics.omega * (l.phase->eval(cosTheta) / (1 - l.f) - pStar) * beam.flux / beam.mu;
        return kappa[li] = c;
    };
    double sum = 0;
    if (mu < 0) {  // upwelling: the sublayers below the plane, and the semi-infinite tail if any
        for (size_t k = plane; k + 1 < g.z.size(); ++k) {
            const double ta = g.tau[k], d = g.tau[k + 1] - ta;
            sum += coefficient(g.layer[k]) / u * std::exp(-ta * a0 - (ta - tk) / u) * h(a0 + 1 / u, d);
        }
        if (!g.bottomPlane) {
            const double ta = g.tau.back();
            sum += coefficient(st.col->layerAt(g.z.back() + 1.0)) / u * std::exp(-ta * a0 - (ta - tk) / u) / (a0 + 1 / u);
        }
        return sum;
    }
    for (size_t k = 0; k < plane; ++k) {  // downwelling: the sublayers above
        const double ta = g.tau[k], tb = g.tau[k + 1], d = tb - ta, x = a0 - 1 / u;
        const double e = x >= 0 ? std::exp(-ta * a0 - (tk - ta) / u) * h(x, d) : std::exp(-tb * a0 - (tk - tb) / u) * h(-x, d);
        sum += coefficient(g.layer[k]) / u * e;
    }
    return sum;
}

// The radiance at plane k in direction (mu signed, phi) from the Fourier modes (+ TMS).
double radianceAt(const Setup& st, const std::vector<ModeField>& modes, size_t k, int i, bool up, double phi,
                  bool tms) {
    double v = 0;
    for (size_t m = 0; m < modes.size(); ++m) {
        const auto& f = up ? modes[m].up[k] : modes[m].down[k];
        v += f[static_cast<size_t>(i)] * std::cos(static_cast<double>(m) * phi);
    }
    // A rough surface's sub-beams spread in azimuth: TMS only where the scattering angle does not
    // depend on it (straight up and straight down), docs/column.md.
    if (!tms || (st.rough && i != st.s.nadir())) return v;
    const double mu = st.s.mu[static_cast<size_t>(i)] * (up ? -1 : 1);
    for (const SubBeam& b : st.beams) {
        if (b.flux <= 0) continue;
        for (size_t a = 0; a < b.psi.size(); ++a)
            for (double sg : {-1.0, 1.0}) {
                const double cosT = mu * b.mu + std::sqrt(std::max(0.0, (1 - mu * mu) * (1 - b.mu * b.mu))) * std::cos(phi - sg * b.psi[a]);
                v += 0.5 * b.fraction[a] * tmsCorrection(st, b, k, mu, std::clamp(cosT, -1.0, 1.0));
            }
    }
    return v;
}

Setup makeSetup(const ColumnBand& col, const std::vector<double>& depths, const SolverOptions& o) {
    for (size_t i = 0; i < depths.size(); ++i) {
        if (!(depths[i] >= 0) || !std::isfinite(depths[i]) || (i > 0 && depths[i] <= depths[i - 1]))
            throw InputError(fmt::format("depths must be finite, >= 0 and strictly increasing (depth {} is {})", i + 1, depths[i]));
        if (col.bottomDepth && depths[i] > *col.bottomDepth + 1e-9)
            throw InputError(fmt::format("depth {} m lies below the bottom at {} m", depths[i], *col.bottomDepth));
    }
    if (col.layers.empty() || col.layers[0].top != 0.0) throw InputError("the column needs a first layer starting at depth 0");
    if (!(col.waterIndex >= 1.0)) throw InputError(fmt::format("water refractive index {} < 1 is not supported", col.waterIndex));
    Setup st;
    st.col = &col;
    st.s = Streams::snellSplit(o.streamsPerHalf, col.waterIndex);
    for (const auto& l : col.layers) st.layers.push_back(scaleLayer(l, st.s.legendreOrder()));
    st.grid = makeGrid(col, st.layers, depths);
    const double cosA = std::cos(col.sunZenith), sinW = std::sin(col.sunZenith) / col.waterIndex;
    st.mu0 = std::sqrt(1 - sinW * sinW);
    const bool sun = col.sunIrradiance > 0 && cosA > 1e-6;
    if (col.surfaceMeanSquareSlope > 0) {
        const int modes = o.radiance ? st.s.legendreOrder() : 1;
        st.rough = roughSurfaceOperators(st.s, col.waterIndex, col.surfaceMeanSquareSlope, modes);
        if (sun) st.beams = transmittedSun(col.sunZenith, col.sunIrradiance, col.waterIndex, col.surfaceMeanSquareSlope);
    } else if (sun) {
        st.beams.push_back({st.mu0, col.sunIrradiance * cosA * (1 - fresnelReflectance(cosA, 1.0, col.waterIndex)), {0.0}, {1.0}});
    }
    if (st.beams.empty()) st.beams.push_back({st.mu0, 0.0, {0.0}, {1.0}});  // the sky alone
    return st;
}

// Ed, Eu, Eod, Eou and Lu at the requested planes; K functions by finite differences in depth.
void fillProfiles(const Setup& st, const std::vector<ModeField>& modes, const SolverOptions& o, ColumnResult* r) {
    const Streams& s = st.s;
    std::vector<double> beam(st.grid.tau.size(), 0.0), beamScalar(beam.size(), 0.0);
    for (const SubBeam& b : st.beams) {
        const std::vector<double> v = beamAt(st, b);
        for (size_t k = 0; k < v.size(); ++k) beam[k] += v[k], beamScalar[k] += v[k] / b.mu;
    }
    for (int k : st.grid.requested) {
        DepthResult d;
        d.depth = st.grid.z[static_cast<size_t>(k)];
        const auto& dn = modes[0].down[static_cast<size_t>(k)];
        const auto& up = modes[0].up[static_cast<size_t>(k)];
        d.EdDirect = beam[static_cast<size_t>(k)];
        d.Ed = d.EdDirect;
        d.Eod = beamScalar[static_cast<size_t>(k)];
        for (int i = 0; i < s.size(); ++i) {
            const double w = 2 * kPi * s.w[static_cast<size_t>(i)], mu = s.mu[static_cast<size_t>(i)];
            d.Ed += w * mu * dn[static_cast<size_t>(i)];
            d.Eod += w * dn[static_cast<size_t>(i)];
            d.Eu += w * mu * up[static_cast<size_t>(i)];
            d.Eou += w * up[static_cast<size_t>(i)];
        }
        d.Lu = radianceAt(st, modes, static_cast<size_t>(k), s.nadir(), true, 0.0, o.tms);
        r->depths.push_back(std::move(d));
    }
    auto& ds = r->depths;
    for (size_t i = 0; i < ds.size() && ds.size() > 1; ++i) {
        const size_t a = i == 0 ? 0 : i - 1, b = i + 1 == ds.size() ? i : i + 1;
        const double dz = ds[b].depth - ds[a].depth;
        ds[i].Kd = -(std::log(ds[b].Ed) - std::log(ds[a].Ed)) / dz;
        ds[i].Ku = -(std::log(ds[b].Eu) - std::log(ds[a].Eu)) / dz;
    }
}

void fillRadiance(const Setup& st, const std::vector<ModeField>& modes, const SolverOptions& o, ColumnResult* r) {
    for (int a = 0; a < o.azimuths; ++a) r->azimuthsDeg.push_back(180.0 * a / (o.azimuths - 1));
    for (size_t q = 0; q < r->depths.size(); ++q) {
        const size_t k = static_cast<size_t>(st.grid.requested[q]);
        auto& table = r->depths[q].radiance;
        for (bool up : {false, true})
            for (int i = 0; i < st.s.size(); ++i) {
                std::vector<double> row;
                for (double phiDeg : r->azimuthsDeg) row.push_back(radianceAt(st, modes, k, i, up, deg2rad(phiDeg), o.tms));
                table.push_back(std::move(row));
            }
    }
}

// Mode m's field: the sky with the first beam, then every further sub-beam, summed.
ModeField solveModeAllBeams(const Setup& st, int m) {
    ModeField f = solveMode(st, m, st.beams[0], true);
    for (size_t b = 1; b < st.beams.size(); ++b) {
        const ModeField g = solveMode(st, m, st.beams[b], false);
        for (size_t k = 0; k < f.down.size(); ++k) {
            f.down[k] = f.down[k] + g.down[k];
            f.up[k] = f.up[k] + g.up[k];
        }
    }
    return f;
}

}  // namespace

ColumnResult solveColumn(const ColumnBand& col, const std::vector<double>& depths, const SolverOptions& o) {
    LITTORAL_CHECK_GE(o.azimuths, 2);
    const Setup st = makeSetup(col, depths, o);
    const int modeCount = o.radiance ? st.s.legendreOrder() : 1;
    std::vector<ModeField> modes;
    for (int m = 0; m < modeCount; ++m) modes.push_back(solveModeAllBeams(st, m));
    ColumnResult r;
    r.band = col.band;
    r.streams = st.s;
    r.sunZenithWater = std::acos(st.mu0);
    fillProfiles(st, modes, o, &r);
    if (o.radiance) fillRadiance(st, modes, o, &r);
    r.EdAbove = (col.sunIrradiance > 0 ? col.sunIrradiance * std::max(0.0, std::cos(col.sunZenith)) : 0.0) + kPi * col.skyRadiance;
    // Water-leaving radiance toward the zenith: the nadir upwelling radiance just below, through
    // the surface (1 - r(0)), divided by n^2 (the radiance of a refracted pencil scales with n^2).
    // Rough: 1 - r(0) becomes, by reciprocity, the transmittance of the rough surface for light from
    // the zenith (Lu taken as constant over the few degrees the zenith ray gathers from).
    const double lu0 = radianceAt(st, modes, 0, st.s.nadir(), true, 0.0, o.tms);
    const double t0 = st.rough ? 1 - st.rough->reflectanceFromAirAtZenith : 1 - fresnelReflectance(1.0, col.waterIndex, 1.0);
    r.LwNadir = lu0 * t0 / (col.waterIndex * col.waterIndex);
    r.Rrs = r.EdAbove > 0 ? r.LwNadir / r.EdAbove : 0.0;
    return r;
}

}  // namespace littoral::column
