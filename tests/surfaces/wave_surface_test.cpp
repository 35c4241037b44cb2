// generateWaveSurface: facetization and decimation (the dissertation's case), mesh invariants the
// scene assembler relies on, sinusoid and flat surfaces, and parameter validation.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "core/progress.h"
#include "core/units.h"
#include "surfaces/facetize.h"
#include "surfaces/surface_stats.h"
#include "surfaces/wave_report.h"
#include "surfaces/wave_surface.h"

using namespace littoral;
using namespace littoral::surfaces;

namespace {
// Progress lines would only clutter the test log.
const bool kQuiet = [] { littoral::Progress::setEnabled(false); return true; }();

// Invariants for closing the surface into a water volume: every triangle faces up, the projected
// areas sum to the rectangle's area (a height field covering it once), the four corners exist,
// and every boundary edge (used by one triangle) lies on an edge of the rectangle.
void expectHeightFieldOverRectangle(const TriMesh& m, double x0, double y0, double x1, double y1) {
    double area = 0;
    for (size_t t = 0; t < m.numTriangles(); ++t) {
        const Vec3 n = m.faceNormalArea(t);
        ASSERT_GT(n.z, 0.0) << "triangle " << t << " does not face up";
        area += 0.5 * n.z;
    }
    EXPECT_NEAR(area / ((x1 - x0) * (y1 - y0)), 1.0, 1e-9);
    int corners = 0;
    for (const auto& p : m.positions)
        if ((p.x == x0 || p.x == x1) && (p.y == y0 || p.y == y1)) ++corners;
    EXPECT_EQ(corners, 4);
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = t[k], b = t[(k + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    int boundary = 0;
    for (const auto& [e, count] : edges) {
        ASSERT_LE(count, 2);
        if (count != 1) continue;
        ++boundary;
        const Point3& a = m.positions[e.first];
        const Point3& b = m.positions[e.second];
        const bool onEdge = (a.x == x0 && b.x == x0) || (a.x == x1 && b.x == x1) || (a.y == y0 && b.y == y0) ||
                            (a.y == y1 && b.y == y1);
        EXPECT_TRUE(onEdge) << a << " - " << b;
    }
    EXPECT_GE(boundary, 4);
}
}  // namespace

// The dissertation's case (Tables 9.5/10.2): 1200 x 1200 at 0.25 m, seed 500, 30,000 triangles.
// Measured: RMS height (area-weighted, about the mean) and per-axis RMS slope (area-weighted
// triangle gradients) of the full-resolution triangulation of the grid and of the decimated
// mesh, with the same estimator (measureMesh). Decimation must keep the RMS height within 2%.
// The slope tolerance is derived, not guessed: a triangle's gradient is the field's gradient
// averaged over the triangle, which removes slope variance. For a window with per-axis second
// moment sw^2 and a Gaussian autocorrelation exp(-r^2 / L^2) (per-axis wavenumber variance
// 2 / L^2), the fraction of x-slope variance removed is 4 sw^2 (2 / L^2) = 8 sw^2 / L^2. A right
// triangle with legs a has sw^2 = a^2 / 18, so the RMS slope drops by (1/2)(8 a^2 / 18 L^2) =
// 2 a^2 / (9 L^2). Uniform triangles of the same count (area A / n each, a^2 = 2 A / n) set the
// tolerance; the quadric decimation concentrates triangles where the surface bends and must do at
// least as well. With L the measured correlation length: 0.28% at 6 m/s, 0.10% at 10 m/s
// (measured errors: 0.06% and 0.02%).
TEST(WaveSurface, DecimationToDissertationTriangleCountKeepsStatistics) {
    for (double U : {6.0, 10.0}) {
        WaveParams p;
        p.windSpeed = U;
        const WaveSurface s = generateWaveSurface(p);
        EXPECT_EQ(s.field.nx, 1201);
        EXPECT_LE(s.mesh.numTriangles(), 30000u);
        EXPECT_GE(s.mesh.numTriangles(), 29000u);
        const SurfaceStats full = measureMesh(triangulate(s.field), s.field, 0.0);
        EXPECT_NEAR(s.actual.rmsHeight / full.rmsHeight, 1.0, 0.02) << U;
        const double a2 = 2.0 * p.sizeX * p.sizeY / static_cast<double>(s.mesh.numTriangles());
        const double slopeTol = 2.0 * a2 / (9.0 * full.correlationLength * full.correlationLength);
        EXPECT_NEAR(s.actual.rmsSlope / full.rmsSlope, 1.0, slopeTol) << U;
        // Not required by the issue, but the scene's roughness scale should survive too: the 1/e
        // length of the rasterised mesh within the same 2% as the height (measured: 0.2%).
        EXPECT_NEAR(s.actual.correlationLength / full.correlationLength, 1.0, 0.02) << U;
        std::printf("U = %g: full grid rms height %.4f slope %.5f L %.2f; %zu triangles: %.4f %.5f %.2f; max dev %.4f m\n",
                    U, full.rmsHeight, full.rmsSlope, full.correlationLength, s.mesh.numTriangles(), s.actual.rmsHeight,
                    s.actual.rmsSlope, s.actual.correlationLength, s.meshMaxDeviation);
        expectHeightFieldOverRectangle(s.mesh, -150, -150, 150, 150);
        // Predicted column of the tables travels with the surface.
        EXPECT_NEAR(s.predicted.rmsHeight, 0.016 * U * U, 1e-12);
        ASSERT_TRUE(s.beaufort.has_value());
        EXPECT_EQ(s.beaufort->number, U == 6.0 ? 4 : 5);
    }
}

// Decimation keeps the rectangle for an off-centre, non-square, anisotropic spectral surface too,
// and vertex normals point up.
TEST(WaveSurface, MeshInvariantsForSpectralModel) {
    WaveParams p;
    p.model = WaveModel::Jonswap;
    p.windSpeed = 7.0;
    p.windDirection = deg2rad(30.0);
    p.fetch = 30000;
    p.sizeX = 80;
    p.sizeY = 50;
    p.centreX = 1000;
    p.centreY = -20;
    p.spacing = 0.5;
    p.triangles = 4000;
    const WaveSurface s = generateWaveSurface(p);
    expectHeightFieldOverRectangle(s.mesh, 960, -45, 1040, 5);
    EXPECT_LE(s.mesh.numTriangles(), 4000u);
    ASSERT_EQ(s.vertexNormals.size(), s.mesh.numVertices());
    for (const auto& n : s.vertexNormals) EXPECT_GT(n.z, 0.0);
    // heightAt interpolates the realised field: exact at grid vertices.
    EXPECT_DOUBLE_EQ(s.heightAt(s.field.x(7), s.field.y(9)), s.field.at(7, 9));
    // JSON carries the keys issue 3 lists.
    const auto j = waveStatsJson(s);
    for (const char* k : {"rms_height", "rms_slope", "correlation_length"}) EXPECT_TRUE(j["predicted"].contains(k)) << k;
    for (const char* k : {"rms_height", "rms_slope", "correlation_length", "mss_upwind", "mss_crosswind"})
        EXPECT_TRUE(j["actual"].contains(k)) << k;
    EXPECT_EQ(j["mesh"]["triangles"].get<size_t>(), s.mesh.numTriangles());
    EXPECT_EQ(j["beaufort"]["number"].get<int>(), 4);
}

// Sinusoid: z = -A cos(k (u - u0)), u along the direction (trough at u0). Every vertex of the
// full and of the decimated mesh is an exact sample (halfedge collapses never move vertices),
// so heights match the formula to rounding. With an integer number of wavelengths along x the
// sampled RMS height is exactly A / sqrt(2).
TEST(WaveSurface, SinusoidHeightsExact) {
    WaveParams p;
    p.model = WaveModel::Sinusoid;
    p.amplitude = 2.0;
    p.wavelength = 5.0;
    p.phase = 0.7;
    p.windDirection = deg2rad(25.0);
    p.sizeX = p.sizeY = 40.0;
    p.spacing = 0.25;
    for (size_t tri : {size_t{0}, size_t{3000}}) {
        p.triangles = tri;
        const WaveSurface s = generateWaveSurface(p);
        const double k = 2 * kPi / p.wavelength, c = std::cos(p.windDirection), sn = std::sin(p.windDirection);
        double worst = 0;
        for (const auto& v : s.mesh.positions)
            worst = std::max(worst, std::abs(v.z - (-p.amplitude * std::cos(k * (v.x * c + v.y * sn - p.phase)))));
        EXPECT_LT(worst, 1e-12) << tri;
        if (tri == 0) {
            EXPECT_EQ(s.mesh.numTriangles(), 2u * 160 * 160);
        } else {
            EXPECT_LE(s.mesh.numTriangles(), 3000u);
        }
    }
    p.windDirection = 0.0;
    p.phase = 0.75;  // a grid column (x0 = -25, spacing 0.25): the trough sits on vertices
    p.triangles = 0;
    p.sizeX = 50.0;  // 10 wavelengths along x
    const WaveSurface s = generateWaveSurface(p);
    EXPECT_NEAR(s.heightAt(0.75, 3.0), -p.amplitude, 1e-12);  // first trough at u = phase
    EXPECT_NEAR(s.heightAt(0.75 + 2.5, 3.0), p.amplitude, 1e-12);  // crest half a wavelength on
    // The measured RMS height is the RMS of the vertex samples about their mean (to rounding) ...
    double sum = 0, sum2 = 0;
    for (double z : s.field.z) sum += z;
    const double mean = sum / s.field.z.size();
    for (double z : s.field.z) sum2 += (z - mean) * (z - mean);
    EXPECT_NEAR(s.grid.rmsHeight, std::sqrt(sum2 / s.field.z.size()), 1e-12);
    // ... and those are A / sqrt(2) but for the closing column, which repeats the first phase:
    // one extra sample in 201 changes the variance by at most 1/201 (0.25% in RMS).
    EXPECT_NEAR(s.grid.rmsHeight / (p.amplitude / std::sqrt(2.0)), 1.0, 0.0025);
    // Per-axis slope: along the wave <zx^2> = (A k)^2 / 2 sampled by forward differences,
    // (2 A / dx)^2 sin^2(k dx / 2) / 2; across it zero.
    const double dx = 0.25, k = 2 * kPi / 5.0;
    EXPECT_NEAR(s.grid.rmsSlopeX, std::sqrt(0.5) * 2 * p.amplitude / dx * std::sin(k * dx / 2), 1e-9);
    EXPECT_NEAR(s.grid.rmsSlopeY, 0.0, 1e-12);
    // Its autocorrelation along the wave is cos(k r): 1/e at r = acos(1/e) / k = 0.9588 m.
    EXPECT_NEAR(s.grid.correlationLengthUpwind, std::acos(std::exp(-1.0)) / k, 0.01);
}

TEST(WaveSurface, FlatSurface) {
    WaveParams p;
    p.model = WaveModel::Flat;
    p.sizeX = p.sizeY = 10.0;
    p.spacing = 1.0;
    p.triangles = 2;
    const WaveSurface s = generateWaveSurface(p);
    for (const auto& v : s.mesh.positions) EXPECT_EQ(v.z, 0.0);
    EXPECT_EQ(s.actual.rmsHeight, 0.0);
    EXPECT_TRUE(std::isnan(s.actual.correlationLength));
    expectHeightFieldOverRectangle(s.mesh, -5, -5, 5, 5);
    EXPECT_LE(s.mesh.numTriangles(), 8u);
}

// One clear InputError per mistake, naming the option and what is allowed.
TEST(WaveSurface, BadParametersAreInputErrors) {
    auto expectError = [](WaveParams p, const std::string& needle) {
        try {
            validateWaveParams(p);
            ADD_FAILURE() << "no error for " << needle;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    WaveParams p;
    p.windSpeed = -3;
    expectError(p, "--wind");
    p.windSpeed = 0;
    expectError(p, "--wind");
    p.windSpeed = 250;
    expectError(p, "<= 40");
    p = WaveParams{};
    p.spacing = 0;
    expectError(p, "--spacing");
    p = WaveParams{};
    p.sizeX = p.sizeY = 50000;
    p.spacing = 0.01;  // 5e6 x 5e6 grid
    expectError(p, "GiB");
    p = WaveParams{};
    p.sizeX = p.sizeY = 100;
    p.spacing = 1;
    p.triangles = 20001;  // the 100 x 100 grid has 20000
    expectError(p, "--triangles");
    p.triangles = 1;
    expectError(p, "--triangles");
    p = WaveParams{};
    p.windSpeed = 0.3;  // L = 0.45 m: the 0.25 m grid cannot resolve it (needs spacing <= L/2)
    expectError(p, "does not resolve");
    p = WaveParams{};
    p.time = 3.0;  // the Beaufort field is static
    expectError(p, "--time");
    p = WaveParams{};
    p.model = WaveModel::Jonswap;
    p.gamma = 0.5;
    expectError(p, "--gamma");
    p = WaveParams{};
    p.sceneKeys = true;
    p.windSpeed = -1;
    expectError(p, "wind_speed");
    // A length no allowed spacing resolves: its advice names significant digits and the smallest
    // spacing, never "use a spacing <= 0.000 m" (hostile round 3, m20).
    p = WaveParams{};
    p.model = WaveModel::Elfouhaily;
    p.windSpeed = 0.01;
    p.sizeX = p.sizeY = 1;
    p.spacing = 0.5;
    p.triangles = 0;
    expectError(p, "wavelength 9.08e-05 m); that needs a spacing <= 4.54e-05 m, below the smallest allowed (0.001 m)");
    p.model = WaveModel::Beaufort;
    expectError(p, "below the smallest allowed (0.001 m): give a stronger wind");
}

// Without a target, the dissertation's 30,000 triangles, or the full grid where that target would
// be refused (a smaller grid) or would smooth cox-munk's facets.
TEST(WaveSurface, DefaultTriangleTarget) {
    WaveParams p;
    EXPECT_EQ(defaultTriangles(p), 30000u);  // 1200 x 1200
    p.sizeX = p.sizeY = 10;
    p.spacing = 1;
    EXPECT_EQ(defaultTriangles(p), 0u);  // 200 triangles
    p.sizeX = p.sizeY = 123;
    EXPECT_EQ(defaultTriangles(p), 30000u);  // 30258 triangles
    p.sizeX = p.sizeY = 122;
    EXPECT_EQ(defaultTriangles(p), 0u);  // 29768
    p.model = WaveModel::CoxMunk;
    p.sizeX = p.sizeY = 300;
    EXPECT_EQ(defaultTriangles(p), 0u);
    p.model = WaveModel::Beaufort;
    p.spacing = 0;  // refused by the checks, which name the spacing
    EXPECT_EQ(defaultTriangles(p), 30000u);
}
