#include "surfaces/surface_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/units.h"
#include "surfaces/fft2d.h"

namespace littoral::surfaces {

namespace {
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInvE = std::exp(-1.0);

struct SlopeSums {
    double area = 0, zx2 = 0, zy2 = 0, up2 = 0, cross2 = 0;
    void add(double a, double zx, double zy, double cu, double su) {
        area += a;
        zx2 += a * zx * zx;
        zy2 += a * zy * zy;
        up2 += a * sqr(cu * zx + su * zy);
        cross2 += a * sqr(-su * zx + cu * zy);
    }
    void finish(SurfaceStats& s) const {
        const double mx = zx2 / area, my = zy2 / area;
        s.rmsSlopeX = std::sqrt(mx);
        s.rmsSlopeY = std::sqrt(my);
        s.rmsSlope = std::sqrt(0.5 * (mx + my));
        s.rmsSlopeTotal = std::sqrt(mx + my);
        s.mssUpwind = up2 / area;
        s.mssCrosswind = cross2 / area;
    }
};

void setCorrelation(SurfaceStats& s, const HeightField& f, double windDir) {
    const Autocorrelation a = autocorrelation(f);
    if (a.px == 0) {
        s.correlationLength = s.correlationLengthUpwind = s.correlationLengthCrosswind = kNaN;
        return;
    }
    s.correlationLength = correlationLengthRadial(a);
    s.correlationLengthUpwind = correlationLengthAlong(a, windDir);
    s.correlationLengthCrosswind = correlationLengthAlong(a, windDir + 0.5 * kPi);
}

// First crossing of 1/e in a sampled decreasing-then-anything curve (r_i, c_i), linear interpolation.
double firstCrossing(const std::vector<double>& r, const std::vector<double>& c) {
    for (size_t i = 1; i < c.size(); ++i)
        if (c[i] <= kInvE && c[i - 1] > kInvE)
            return r[i - 1] + (c[i - 1] - kInvE) / (c[i - 1] - c[i]) * (r[i] - r[i - 1]);
    return kNaN;
}
}  // namespace

SurfaceStats measureHeightField(const HeightField& f, double windDir) {
    SurfaceStats s;
    // Heights over the unique samples.
    const int ux = f.periodic ? f.nx - 1 : f.nx, uy = f.periodic ? f.ny - 1 : f.ny;
    double sum = 0, sum2 = 0;
    for (int j = 0; j < uy; ++j)
        for (int i = 0; i < ux; ++i) sum += f.at(i, j);
    const double n = static_cast<double>(ux) * uy;
    s.meanHeight = sum / n;
    for (int j = 0; j < uy; ++j)
        for (int i = 0; i < ux; ++i) sum2 += sqr(f.at(i, j) - s.meanHeight);
    s.rmsHeight = std::sqrt(sum2 / n);
    // Slopes of the two triangles of each cell (equal areas, so plain averages).
    const double dx = f.dx(), dy = f.dy(), cu = std::cos(windDir), su = std::sin(windDir);
    SlopeSums ss;
    for (int j = 0; j + 1 < f.ny; ++j)
        for (int i = 0; i + 1 < f.nx; ++i) {
            const double z00 = f.at(i, j), z10 = f.at(i + 1, j), z11 = f.at(i + 1, j + 1), z01 = f.at(i, j + 1);
            ss.add(1.0, (z10 - z00) / dx, (z11 - z10) / dy, cu, su);  // (i,j),(i+1,j),(i+1,j+1)
            ss.add(1.0, (z11 - z01) / dx, (z01 - z00) / dy, cu, su);  // (i,j),(i+1,j+1),(i,j+1)
        }
    ss.finish(s);
    setCorrelation(s, f, windDir);
    return s;
}

HeightField rasterizeMesh(const TriMesh& mesh, const HeightField& ref) {
    HeightField r = ref;
    std::vector<char> hit(r.z.size(), 0);
    const double dx = ref.dx(), dy = ref.dy();
    for (const auto& t : mesh.triangles) {
        const Point3& a = mesh.positions[t[0]];
        const Point3& b = mesh.positions[t[1]];
        const Point3& c = mesh.positions[t[2]];
        const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (det == 0.0) continue;
        const double eps = 1e-9;
        const int i0 = std::max(0, static_cast<int>(std::floor((std::min({a.x, b.x, c.x}) - ref.x0) / dx - eps)));
        const int i1 = std::min(ref.nx - 1, static_cast<int>(std::ceil((std::max({a.x, b.x, c.x}) - ref.x0) / dx + eps)));
        const int j0 = std::max(0, static_cast<int>(std::floor((std::min({a.y, b.y, c.y}) - ref.y0) / dy - eps)));
        const int j1 = std::min(ref.ny - 1, static_cast<int>(std::ceil((std::max({a.y, b.y, c.y}) - ref.y0) / dy + eps)));
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const double px = ref.x(i), py = ref.y(j);
                // Barycentric coordinates of (px, py) in the triangle's horizontal projection.
                const double l1 = ((px - a.x) * (c.y - a.y) - (c.x - a.x) * (py - a.y)) / det;
                const double l2 = ((b.x - a.x) * (py - a.y) - (px - a.x) * (b.y - a.y)) / det;
                const double l0 = 1.0 - l1 - l2;
                if (l0 < -eps || l1 < -eps || l2 < -eps) continue;
                const size_t idx = static_cast<size_t>(j) * ref.nx + i;
                r.z[idx] = l0 * a.z + l1 * b.z + l2 * c.z;
                hit[idx] = 1;
            }
    }
    const size_t misses = static_cast<size_t>(std::count(hit.begin(), hit.end(), 0));
    LITTORAL_CHECK_EQ(misses, size_t{0});  // the mesh must cover the rectangle
    return r;
}

SurfaceStats measureMesh(const TriMesh& mesh, const HeightField& ref, double windDir, double* maxDeviation) {
    SurfaceStats s;
    const double cu = std::cos(windDir), su = std::sin(windDir);
    SlopeSums ss;
    double area = 0, iz = 0;
    for (const auto& t : mesh.triangles) {
        const Point3& a = mesh.positions[t[0]];
        const Point3& b = mesh.positions[t[1]];
        const Point3& c = mesh.positions[t[2]];
        const Vec3 nrm = cross(b - a, c - a);
        const double A = 0.5 * std::abs(nrm.z);  // projected (horizontal) area, m^2
        if (A == 0.0) continue;
        area += A;
        iz += A * (a.z + b.z + c.z) / 3.0;
        ss.add(A, -nrm.x / nrm.z, -nrm.y / nrm.z, cu, su);
    }
    s.meanHeight = iz / area;
    // Int (z - mean)^2 dA over a linear triangle = A/6 (Sum d_i^2 + Sum_{i<j} d_i d_j), d = z - mean.
    double iz2 = 0;
    for (const auto& t : mesh.triangles) {
        const Point3& a = mesh.positions[t[0]];
        const Point3& b = mesh.positions[t[1]];
        const Point3& c = mesh.positions[t[2]];
        const double A = 0.5 * std::abs(cross(b - a, c - a).z);
        const double d0 = a.z - s.meanHeight, d1 = b.z - s.meanHeight, d2 = c.z - s.meanHeight;
        iz2 += A / 6.0 * (d0 * d0 + d1 * d1 + d2 * d2 + d0 * d1 + d1 * d2 + d0 * d2);
    }
    s.rmsHeight = std::sqrt(iz2 / area);
    ss.finish(s);
    const HeightField r = rasterizeMesh(mesh, ref);
    if (maxDeviation) {
        double md = 0;
        for (size_t i = 0; i < r.z.size(); ++i) md = std::max(md, std::abs(r.z[i] - ref.z[i]));
        *maxDeviation = md;
    }
    setCorrelation(s, r, windDir);
    return s;
}

Autocorrelation autocorrelation(const HeightField& f) {
    Autocorrelation a;
    const int ux = f.periodic ? f.nx - 1 : f.nx, uy = f.periodic ? f.ny - 1 : f.ny;
    double mean = 0;
    for (int j = 0; j < uy; ++j)
        for (int i = 0; i < ux; ++i) mean += f.at(i, j);
    mean /= static_cast<double>(ux) * uy;
    // Circular for a periodic field; otherwise zero-padded to twice the size so lags do not wrap.
    const int px = f.periodic ? ux : 2 * ux, py = f.periodic ? uy : 2 * uy;
    Fft2dReal fft(px, py);
    double* x = fft.real();
    std::fill(x, x + static_cast<size_t>(px) * py, 0.0);
    double var = 0;
    for (int j = 0; j < uy; ++j)
        for (int i = 0; i < ux; ++i) {
            const double d = f.at(i, j) - mean;
            x[static_cast<size_t>(j) * px + i] = d;
            var += d * d;
        }
    if (!(var > 0)) return a;  // flat: no autocorrelation
    fft.forward();
    // Wiener-Khinchin: autocorrelation = inverse transform of |X_k|^2.
    const size_t ns = static_cast<size_t>(fft.halfX()) * py;
    for (size_t k = 0; k < ns; ++k) fft.spectrum()[k] = std::norm(fft.spectrum()[k]);
    fft.backward();
    a.px = px;
    a.py = py;
    a.dx = f.dx();
    a.dy = f.dy();
    a.maxLagX = f.periodic ? ux / 2 : ux - 1;
    a.maxLagY = f.periodic ? uy / 2 : uy - 1;
    a.c.resize(static_cast<size_t>(px) * py);
    for (int j = 0; j < py; ++j)
        for (int i = 0; i < px; ++i) {
            double v = x[static_cast<size_t>(j) * px + i];
            if (!f.periodic) {
                // Normalise each lag by its number of overlapping sample pairs.
                const int li = i <= px / 2 ? i : px - i, lj = j <= py / 2 ? j : py - j;
                const double overlap = static_cast<double>(ux - li) * (uy - lj);
                v = overlap > 0 ? v / overlap : 0.0;
            }
            a.c[static_cast<size_t>(j) * px + i] = v;
        }
    const double c0 = a.c[0];
    for (double& v : a.c) v /= c0;
    return a;
}

double correlationLengthRadial(const Autocorrelation& a) {
    if (a.px == 0) return kNaN;
    const double rMax = std::min(a.maxLagX * a.dx, a.maxLagY * a.dy);
    const double bin = std::min(a.dx, a.dy);
    const int nb = static_cast<int>(rMax / bin) + 1;
    std::vector<double> sumC(nb, 0.0), sumR(nb, 0.0), cnt(nb, 0.0);
    const int lx = std::min(a.maxLagX, static_cast<int>(rMax / a.dx) + 1);
    const int ly = std::min(a.maxLagY, static_cast<int>(rMax / a.dy) + 1);
    for (int lj = -ly; lj <= ly; ++lj)
        for (int li = -lx; li <= lx; ++li) {
            const double r = std::hypot(li * a.dx, lj * a.dy);
            if (r > rMax) continue;
            const int b = static_cast<int>(std::lround(r / bin));
            if (b >= nb) continue;
            sumC[b] += a.at(li, lj);
            sumR[b] += r;
            cnt[b] += 1;
        }
    std::vector<double> r, c;
    for (int b = 0; b < nb; ++b)
        if (cnt[b] > 0) {
            r.push_back(sumR[b] / cnt[b]);
            c.push_back(sumC[b] / cnt[b]);
        }
    return firstCrossing(r, c);
}

double correlationLengthAlong(const Autocorrelation& a, double dir) {
    if (a.px == 0) return kNaN;
    const double ux = std::cos(dir), uy = std::sin(dir);
    // Stay inside the lag range on both axes.
    double rMax = std::numeric_limits<double>::infinity();
    if (std::abs(ux) > 1e-12) rMax = std::min(rMax, (a.maxLagX - 1) * a.dx / std::abs(ux));
    if (std::abs(uy) > 1e-12) rMax = std::min(rMax, (a.maxLagY - 1) * a.dy / std::abs(uy));
    const double step = 0.25 * std::min(a.dx, a.dy);
    std::vector<double> r, c;
    for (double d = 0; d <= rMax; d += step) {
        // Bilinear interpolation of the lag array at (d ux / dx, d uy / dy).
        const double gx = d * ux / a.dx, gy = d * uy / a.dy;
        const int i = static_cast<int>(std::floor(gx)), j = static_cast<int>(std::floor(gy));
        const double fx = gx - i, fy = gy - j;
        const double v = (1 - fy) * ((1 - fx) * a.at(i, j) + fx * a.at(i + 1, j)) +
                         fy * ((1 - fx) * a.at(i, j + 1) + fx * a.at(i + 1, j + 1));
        r.push_back(d);
        c.push_back(v);
        if (v <= kInvE) break;
    }
    return firstCrossing(r, c);
}

}  // namespace littoral::surfaces
