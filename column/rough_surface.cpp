#include "column/rough_surface.h"

#include <algorithm>
#include <cmath>

#include "column/column_solver.h"
#include "core/error.h"
#include "core/units.h"

namespace littoral::column {

std::vector<Facet> slopeQuadrature(double s2, int radial, int azimuthal) {
    LITTORAL_CHECK_GT(s2, 0.0);
    LITTORAL_CHECK_GE(radial, 1);
    LITTORAL_CHECK_GE(azimuthal, 1);
    std::vector<Facet> f;
    f.reserve(static_cast<size_t>(radial) * static_cast<size_t>(azimuthal));
    const double w = 1.0 / (static_cast<double>(radial) * azimuthal);
    for (int k = 0; k < radial; ++k) {
        // u = 1 - exp(-|z|^2/s2) is uniform under P: |z| = sqrt(-s2 ln(1 - u)).
        const double u = (k + 0.5) / radial, z = std::sqrt(-s2 * std::log1p(-u));
        for (int l = 0; l < azimuthal; ++l) {
            const double a = 2 * kPi * (l + 0.5) / azimuthal;
            f.push_back({z * std::cos(a), z * std::sin(a), w});
        }
    }
    return f;
}

SurfaceScatter scatterAtSurface(const std::vector<Facet>& facets, double nWater, double dx, double dy, double dz) {
    LITTORAL_CHECK(dz != 0.0);
    const bool fromAir = dz < 0;
    const double eta = fromAir ? 1.0 / nWater : nWater;  // n_incident / n_transmitted
    SurfaceScatter out;
    double total = 0;
    for (const Facet& f : facets) {
        const double inv = 1.0 / std::sqrt(1 + f.zx * f.zx + f.zy * f.zy);
        // Facet normal toward the incident side (upward from the air, downward from the water).
        const double sgn = fromAir ? 1.0 : -1.0;
        const double nx = -f.zx * inv * sgn, ny = -f.zy * inv * sgn, nz = inv * sgn;
        const double cosI = -(dx * nx + dy * ny + dz * nz);
        if (cosI <= 0) continue;  // the facet faces away from the ray
        // Intercept probability: projected facet area per unit mean-plane area seen along d.
        const double w = f.weight * cosI / (std::abs(dz) * inv);
        total += w;
        const double r = fresnelReflectance(cosI, fromAir ? 1.0 : nWater, fromAir ? nWater : 1.0);
        FacetOutcome rf{dx + 2 * cosI * nx, dy + 2 * cosI * ny, dz + 2 * cosI * nz, w * r};
        if ((rf.dz < 0) == fromAir) rf.dz = -rf.dz;  // would meet the surface again: mirrored
        out.reflected.push_back(rf);
        if (r >= 1.0) continue;
        const double k = 1 - eta * eta * (1 - cosI * cosI), ct = std::sqrt(std::max(0.0, k));
        FacetOutcome tr{eta * dx + (eta * cosI - ct) * nx, eta * dy + (eta * cosI - ct) * ny,
                        eta * dz + (eta * cosI - ct) * nz, w * (1 - r)};
        if ((tr.dz < 0) != fromAir) tr.dz = -tr.dz;
        out.transmitted.push_back(tr);
    }
    LITTORAL_CHECK_GT(total, 0.0);
    for (auto* v : {&out.reflected, &out.transmitted})
        for (FacetOutcome& o : *v) o.weight /= total;
    for (const FacetOutcome& o : out.reflected) out.reflectance += o.weight;
    for (const FacetOutcome& o : out.transmitted) out.transmittance += o.weight;
    return out;
}

namespace {

// Upper edges of the stream cells (the Gauss weights laid end to end); the nadir node (weight 0)
// has no cell.
std::vector<double> cellEdges(const Streams& s) {
    std::vector<double> e;
    double b = 0;
    for (int i = 0; i + 1 < s.size(); ++i) e.push_back(b += s.w[static_cast<size_t>(i)]);
    e.back() = 1.0;
    return e;
}

int cellOf(const std::vector<double>& edges, double mu) {
    const auto it = std::lower_bound(edges.begin(), edges.end(), mu);
    return static_cast<int>(std::min<std::ptrdiff_t>(it - edges.begin(), static_cast<std::ptrdiff_t>(edges.size()) - 1));
}

}  // namespace

RoughSurfaceOperators roughSurfaceOperators(const Streams& s, double nWater, double s2, int modes) {
    const int n = s.size();
    const std::vector<Facet> facets = slopeQuadrature(s2);
    const std::vector<double> edges = cellEdges(s);
    RoughSurfaceOperators op;
    op.reflectionFromBelow.assign(static_cast<size_t>(modes), Matrix(n, n));
    for (int j = 0; j < n; ++j) {
        const double mu = s.mu[static_cast<size_t>(j)];
        const SurfaceScatter sc = scatterAtSurface(facets, nWater, std::sqrt(std::max(0.0, 1 - mu * mu)), 0.0, mu);
        op.reflectanceFromBelow.push_back(sc.reflectance);
        op.skyTransmission.push_back(nWater * nWater * (1 - sc.reflectance));  // reciprocity, n^2 law
        if (s.w[static_cast<size_t>(j)] == 0) continue;  // the nadir stream enters no integral
        for (const FacetOutcome& o : sc.reflected) {
            const int i = cellOf(edges, -o.dz);
            const double psi = std::atan2(o.dy, o.dx);
            for (int m = 0; m < modes; ++m) op.reflectionFromBelow[static_cast<size_t>(m)](i, j) += o.weight * std::cos(m * psi);
        }
    }
    for (Matrix& r : op.reflectionFromBelow) {
        for (int i = 0; i + 1 < n; ++i)
            for (int j = 0; j < n; ++j)  // flux fraction -> radiance: mu_j w_j / (mu_i w_i)
                r(i, j) *= s.mu[static_cast<size_t>(j)] * s.w[static_cast<size_t>(j)] /
                           (s.mu[static_cast<size_t>(i)] * s.w[static_cast<size_t>(i)]);
        for (int j = 0; j < n; ++j) r(n - 1, j) = r(n - 2, j);  // straight down: the adjacent cell's radiance
    }
    op.reflectanceFromAirAtZenith = scatterAtSurface(facets, nWater, 0, 0, -1).reflectance;
    return op;
}

double SubBeam::modeFactor(int m) const {
    double c = 0;
    for (size_t a = 0; a < psi.size(); ++a) c += fraction[a] * std::cos(m * psi[a]);
    return c;
}

std::vector<SubBeam> transmittedSun(double sunZenith, double e0, double nWater, double s2, int muBins, int psiBins) {
    const SurfaceScatter sc = scatterAtSurface(slopeQuadrature(s2), nWater, std::sin(sunZenith), 0, -std::cos(sunZenith));
    double lo = kPi, hi = 0;
    for (const FacetOutcome& o : sc.transmitted) lo = std::min(lo, std::acos(-o.dz)), hi = std::max(hi, std::acos(-o.dz));
    const int nb = hi - lo < 1e-9 ? 1 : muBins;
    // Per (mu bin, psi bin): flux, flux / mu, flux psi.
    std::vector<double> f(static_cast<size_t>(nb * psiBins)), fOverMu(f.size()), fPsi(f.size());
    const double e = e0 * std::cos(sunZenith);
    for (const FacetOutcome& o : sc.transmitted) {
        const double mu = -o.dz, psi = std::abs(std::atan2(o.dy, o.dx));
        const int b = std::min(nb - 1, static_cast<int>((std::acos(mu) - lo) / std::max(hi - lo, 1e-300) * nb));
        const int a = std::min(psiBins - 1, static_cast<int>(psi / kPi * psiBins));
        const size_t k = static_cast<size_t>(b * psiBins + a);
        f[k] += e * o.weight, fOverMu[k] += e * o.weight / mu, fPsi[k] += e * o.weight * psi;
    }
    std::vector<SubBeam> beams;
    for (int b = 0; b < nb; ++b) {
        SubBeam sb;
        double inv = 0;
        for (int a = 0; a < psiBins; ++a) {
            const size_t k = static_cast<size_t>(b * psiBins + a);
            if (f[k] <= 0) continue;
            sb.flux += f[k], inv += fOverMu[k];
            sb.psi.push_back(fPsi[k] / f[k]);
            sb.fraction.push_back(f[k]);
        }
        if (sb.flux <= 0) continue;
        sb.mu = sb.flux / inv;  // keeps the mean path length 1/mu of the bin
        for (double& x : sb.fraction) x /= sb.flux;
        beams.push_back(std::move(sb));
    }
    return beams;
}

}  // namespace littoral::column
