// Wall time until every cell of Mobley et al.'s (1993) problems 1 (albedo 0.9, 0.2) and 6 is within
// tolerance, with the path estimator on all cores (issue 8's benchmark; aim: <= 60 s each on 2 cores).
//
// Each problem is the scene file in data_synthetic/mobley1993/. Its probes are evaluated with a
// sample budget that doubles, starting from 1/16 of the per-probe counts in the file, until every
// cell passes the test's criterion (tests/pipelines/mobley1993_test.cpp): relative difference
// within max(3 s/mean, 3 se/mean) + print rounding, and se/mean <= max(s/mean, 1 %). The reported
// time is the sum over all attempts (what a user waiting for a converged answer would wait), plus
// the time of the last attempt alone.
//
// Usage: bench_mobley [SOURCE_DIR]   (default: the source tree this binary was configured from)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>

#include "core/log.h"
#include "core/progress.h"
#include "render/estimator.h"
#include "render/probes.h"
#include "scenegen/assemble.h"
#include "pipelines/reference/mobley1993.h"

namespace fs = std::filesystem;
using namespace littoral;
namespace mb = littoral::reference::mobley1993;

namespace {

struct Problem {
    const char* file;
    int problem;
    double w0;
    std::map<std::string, double> tauOfProbe;
};

double seconds(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    Progress::setEnabled(false);
    log::setLevel(log::Level::Warn);
    render::registerEstimatorKinds();  // the scene reader reads their descriptors
    const fs::path src = argc > 1 ? fs::path(argv[1]) : fs::path(LITTORAL_SOURCE_DIR_BENCH);
    const Problem problems[] = {
        {"problem1_albedo09.yaml", 1, 0.9, {{"tau1", 1}, {"tau5", 5}, {"tau10", 10}}},
        {"problem1_albedo02.yaml", 1, 0.2, {{"tau1", 1}, {"tau5", 5}, {"tau10", 10}}},
        {"problem6.yaml", 6, 0.2, {{"tau1", 1}, {"tau5", 5}}},
    };
    std::printf("%-24s %10s %12s %14s %s\n", "problem", "scale", "last run s", "total s", "cells passing");
    for (const Problem& pb : problems) {
        const fs::path scene = src / "data_synthetic" / "mobley1993" / pb.file;
        const fs::path irDir = fs::temp_directory_path() / (std::string("bench_mobley_") + pb.file);
        const auto built = scenegen::buildScene(scene.string(), irDir);
        double total = 0;
        for (double scale = 1.0 / 16; scale <= 8; scale *= 2) {
            ir::SceneIR ir = built.ir;
            for (auto& p : ir.probes) p.samples = std::max(render::makeRenderConfig(ir).probeBatches * 2,
                                                           static_cast<int>(p.samples.value_or(4096) * scale));
            const auto t0 = std::chrono::steady_clock::now();
            const render::Scene sc(ir, irDir);
            const render::EstimatorSet est(sc);
            render::RenderOptions ro;
            ro.progress = false;
            int passing = 0, cells = 0;
            for (size_t i = 0; i < ir.probes.size(); ++i) {
                const auto values = render::evaluateProbe(sc, est, ir.probes[i], static_cast<int>(i), ro);
                const mb::Row* row = mb::find(pb.problem, pb.w0, pb.tauOfProbe.at(ir.probes[i].name));
                for (const auto& v : values) {
                    const mb::Cell& cell = v.quantity == "Ed" ? row->Ed : v.quantity == "Eou" ? row->Eou : row->Lu;
                    const double rel = v.mean[0] / cell.mean - 1;
                    const bool ok = std::abs(rel) <= mb::toleranceWithRounding(cell, v.stderr_[0]) &&
                                    v.stderr_[0] / v.mean[0] <= std::max(cell.sOverMean, 0.01);
                    passing += ok;
                    ++cells;
                }
            }
            const double t = seconds(t0);
            total += t;
            std::printf("%-24s %10.4g %12.2f %14.2f %d / %d\n", pb.file, scale, t, total, passing, cells);
            std::fflush(stdout);
            if (passing == cells) break;
        }
        fs::remove_all(irDir);
    }
    return 0;
}
