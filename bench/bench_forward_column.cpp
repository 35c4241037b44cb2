// The yardstick of issue 19: a one-dimensional forward Monte Carlo with plane-crossing tallies, the
// method of open ocean-optics column codes, against Littoral's probes on the same column, side by
// side in one run on one thread.
//
// The column is Mobley et al.'s (1993) problem 2 at albedo 0.9 (data_synthetic/mobley1993/
// problem2_albedo09.yaml): c = 1 m^-1, b = 0.9, the Petzold average-particle phase function,
// n = 1.34, a flat surface, a point sun at 60 deg with Ed(0+) = 0.5, black sky, a black bottom at
// tau = 60. Cells: Ed and Eou at tau = 1, 5, 10.
//
// The yardstick is written here, sharing nothing with render/ but the Petzold table (core/):
// photons enter through the flat surface with the Fresnel transmittance as their weight, fly
// exponential free paths, lose the albedo at each collision (survival weighting, roulette below a
// weight of 0.25), turn by the phase function and reflect at the surface from below with the
// Fresnel reflectance (total internal reflection beyond the critical angle). Each crossing of a
// tally plane adds w (Ed, downward) or w / |mu| (Eou, upward; 2 / 0.01 below |mu| = 0.01, the
// grazing correction of render/forward_tally.cpp). A 5-degree cone of upward
// crossings gives Lu for information (the cone's average, not the nadir value).
//
// For each method the run reports the wall time, the worst relative standard error over the
// cells, and the time it would need for a worst error of 1 % (t x (se / 1 %)^2, standard errors
// falling as 1 / sqrt(N)). The ratio of those times is the figure docs/performance.md tabulates.
//
// Usage: bench_forward_column [PHOTONS] [SOURCE_DIR]   (default 1,000,000 photons each)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "core/log.h"
#include "core/phase_functions.h"
#include "core/progress.h"
#include "render/estimator.h"
#include "render/probes.h"
#include "scenegen/assemble.h"

namespace fs = std::filesystem;
using namespace littoral;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kN = 1.34, kC = 1.0, kAlbedo = 0.9, kSunZenithDeg = 60, kBottom = 60;
constexpr double kTaus[] = {1, 5, 10};
// Batches of both methods. The ratio compares the worst cells' squared standard errors, and a
// standard error from B batches is itself uncertain by about 1 / sqrt(2 (B - 1)): 16 % at 20
// batches (33 % in its square), 5 % at 200. Both sides get the same count.
constexpr int kBatches = 200;

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Unpolarised Fresnel reflectance from medium n1 into n2 at incidence cosine ci (1 beyond the
// critical angle).
double fresnel(double ci, double n1, double n2) {
    const double s2 = (n1 / n2) * (n1 / n2) * (1 - ci * ci);
    if (s2 >= 1) return 1;
    const double ct = std::sqrt(1 - s2);
    const double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct), rp = (n1 * ct - n2 * ci) / (n1 * ct + n2 * ci);
    return 0.5 * (rs * rs + rp * rp);
}

struct Tallies {
    double ed[3] = {0, 0, 0}, eou[3] = {0, 0, 0}, lu[3] = {0, 0, 0};
};

// One batch of photons of the yardstick. Depth d >= 0 downward; mu = cosine of the direction with
// the downward vertical.
Tallies yardstickBatch(uint64_t photons, uint64_t seed, const TabulatedPhase& petzold) {
    std::mt19937_64 gen(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double cs = std::cos(kSunZenithDeg * kPi / 180), ss = std::sin(kSunZenithDeg * kPi / 180);
    const double T = 1 - fresnel(cs, 1.0, kN);
    const double mu0 = std::sqrt(1 - ss * ss / (kN * kN));
    const double coneCos = std::cos(5 * kPi / 180), coneSr = 2 * kPi * (1 - coneCos);
    Tallies t;
    for (uint64_t p = 0; p < photons; ++p) {
        double d = 0, w = T;
        double ux = std::sqrt(1 - mu0 * mu0), uy = 0, mu = mu0;  // direction (x, y, down)
        for (;;) {
            const double s = -std::log(1 - U(gen)) / kC;
            double dn = d + mu * s;
            const bool bottom = dn >= kBottom, surface = dn <= 0;
            dn = std::clamp(dn, 0.0, kBottom);
            for (int k = 0; k < 3; ++k) {
                const double z = kTaus[k] / kC;
                if (mu > 0 && d < z && z <= dn) t.ed[k] += w;
                if (mu < 0 && dn <= z && z < d) {
                    t.eou[k] += -mu >= 0.01 ? w / -mu : w * 200;  // the grazing correction Littoral uses
                    if (-mu > coneCos) t.lu[k] += w / (-mu * coneSr);
                }
            }
            if (bottom) break;
            d = dn;
            if (surface) {  // internal reflection at the flat surface
                w *= fresnel(-mu, kN, 1.0);
                mu = -mu;
            } else {
                w *= kAlbedo;
                const double c = petzold.sampleCos(U(gen)), phi = 2 * kPi * U(gen);
                const double sn = std::sqrt(std::max(0.0, 1 - c * c));
                // Rotate (ux, uy, mu) by the scattering angle: a frame around the old direction.
                double ax, ay, az;
                if (std::abs(mu) < 0.999) {
                    const double l = std::sqrt(ux * ux + uy * uy);
                    ax = -uy / l, ay = ux / l, az = 0;
                } else {
                    ax = 1, ay = 0, az = 0;
                }
                const double bx = uy * az - mu * ay, by = mu * ax - ux * az, bz = ux * ay - uy * ax;
                const double nx = c * ux + sn * (std::cos(phi) * ax + std::sin(phi) * bx);
                const double ny = c * uy + sn * (std::cos(phi) * ay + std::sin(phi) * by);
                const double nz = c * mu + sn * (std::cos(phi) * az + std::sin(phi) * bz);
                const double l = std::sqrt(nx * nx + ny * ny + nz * nz);
                ux = nx / l, uy = ny / l, mu = nz / l;
            }
            if (w < 0.25) {
                if (U(gen) >= w / 0.25) break;
                w = 0.25;
            }
        }
    }
    return t;
}

struct Cell {
    double mean, se;
};
Cell stats(const std::vector<double>& batchMeans) {
    double s = 0, s2 = 0;
    for (double x : batchMeans) s += x, s2 += x * x;
    const double n = static_cast<double>(batchMeans.size()), m = s / n;
    return {m, std::sqrt(std::max(0.0, (s2 - n * m * m) / (n - 1)) / n)};
}

void report(const char* method, double t, const std::vector<std::pair<std::string, Cell>>& cells) {
    double worst = 0;
    for (const auto& [name, c] : cells) {
        std::printf("  %-8s %-10s %.6e +- %.2e (%.3f %%)\n", method, name.c_str(), c.mean, c.se, 100 * c.se / c.mean);
        worst = std::max(worst, c.se / c.mean);
    }
    std::printf("%-10s wall %.2f s, worst relative se %.3f %%, time to 1 %%: %.2f s\n", method, t, 100 * worst,
                t * (worst / 0.01) * (worst / 0.01));
}

double timeToOnePercent(double t, const std::vector<std::pair<std::string, Cell>>& cells) {
    double worst = 0;
    for (const auto& [name, c] : cells) worst = std::max(worst, c.se / c.mean);
    return t * (worst / 0.01) * (worst / 0.01);
}

}  // namespace

int main(int argc, char** argv) {
    Progress::setEnabled(false);
    log::setLevel(log::Level::Warn);
    render::registerEstimatorKinds();
    const uint64_t photons = argc > 1 ? std::stoull(argv[1]) : 1000000;
    const fs::path src = argc > 2 ? fs::path(argv[2]) : fs::path(LITTORAL_SOURCE_DIR_BENCH);

    // The yardstick, one thread.
    const auto petzold = petzoldAverageParticleTable();
    auto t0 = std::chrono::steady_clock::now();
    std::vector<double> ed[3], eou[3], lu[3];
    const double edTop = std::cos(kSunZenithDeg * kPi / 180);  // Ed(0+) per unit of the beam's irradiance
    for (int b = 0; b < kBatches; ++b) {
        const uint64_t n = photons / kBatches;
        const Tallies t = yardstickBatch(n, 1000 + b, *petzold);
        for (int k = 0; k < 3; ++k) {
            ed[k].push_back(edTop * t.ed[k] / n);
            eou[k].push_back(edTop * t.eou[k] / n);
            lu[k].push_back(edTop * t.lu[k] / n);
        }
    }
    const double tYard = seconds(t0);
    std::vector<std::pair<std::string, Cell>> yard;
    for (int k = 0; k < 3; ++k) {
        yard.push_back({"Ed(" + std::to_string(static_cast<int>(kTaus[k])) + ")", stats(ed[k])});
        yard.push_back({"Eou(" + std::to_string(static_cast<int>(kTaus[k])) + ")", stats(eou[k])});
    }
    report("yardstick", tYard, yard);
    for (int k = 0; k < 3; ++k) {
        const Cell c = stats(lu[k]);
        std::printf("  yardstick Lu(%g), 5-deg cone: %.6e +- %.2e\n", kTaus[k], c.mean, c.se);
    }

    // Littoral's probes on the scene file (Ed and Eou; forward tallies), one thread.
    const fs::path scene = src / "data_synthetic" / "mobley1993" / "problem2_albedo09.yaml";
    const fs::path irDir = fs::temp_directory_path() / "bench_forward_column_ir";
    const auto built = scenegen::buildScene(scene.string(), irDir);
    ir::SceneIR ir = built.ir;
    for (auto& p : ir.probes) p.quantities = {"Ed", "Eou"};
    ir.render.settings.set("probe_photons", ParamValue(static_cast<int64_t>(photons)));
    ir.render.settings.set("probe_batches", ParamValue(static_cast<int64_t>(kBatches)));
    t0 = std::chrono::steady_clock::now();
    const render::Scene sc(ir, irDir);
    const render::EstimatorSet est(sc);
    render::RenderOptions ro;
    ro.progress = false;
    ro.threads = 1;
    const auto values = render::evaluateProbes(sc, est, ro);
    const double tLit = seconds(t0);
    std::vector<std::pair<std::string, Cell>> lit;
    for (const auto& v : values)
        lit.push_back({v.quantity + "(" + v.probe.substr(3) + ")", {v.mean[0], v.stderr_[0]}});
    report("littoral", tLit, lit);
    std::printf("time to 1 %%: littoral / yardstick = %.3f\n", timeToOnePercent(tLit, lit) / timeToOnePercent(tYard, yard));
    fs::remove_all(irDir);
    return 0;
}
