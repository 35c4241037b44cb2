// `littoral study image-quality --out DIR`: the Chapter 9 image-quality study (SNR on each side of
// a submerged step target's edge, ESF/LSF and FWHM against the photon-map search radius and photon
// density); docs/image-quality.md.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "core/log.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_image_quality.h"

namespace {

littoral::CommandRegistrar registerStudy{"study", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("study", "Parameter studies that render many scenes and tabulate and plot the results");
    cmd->require_subcommand(1);
    auto* iq = cmd->add_subcommand("image-quality",
                                   "Chapter 9: SNR and edge/line spread functions of a submerged step target against "
                                   "the photon-map search radius and photon density");
    auto o = std::make_shared<littoral::pipelines::ImageQualityOptions>();
    iq->add_option("--out", o->out, "Output folder (runs/, image_quality.csv, esf_*.csv, *.svg)")->required();
    iq->add_option("--depths", o->depths, "Target depths, m (the dissertation: 1.0 2.5 3.5 5.0)")->capture_default_str();
    iq->add_option("--radii", o->radii, "Search radii, m (surface and volume alike)")->capture_default_str();
    iq->add_option("--densities", o->densities, "Volume photon densities, photons per m^3")->capture_default_str();
    iq->add_option("--surface-per-volume", o->surfacePerVolume,
                   "Surface photons per m^2 for each volume photon per m^3 (5.5: the coastal scene's 5500 per m^2 at "
                   "1000 per m^3)")
        ->check(CLI::Range(0.01, 1000.0))
        ->capture_default_str();
    iq->add_option("--water", o->water, "Water type (Table 9.6): coastal, bay, turbid")->capture_default_str();
    iq->add_option("--g", o->g, "Henyey-Greenstein asymmetry of the water's phase function")->capture_default_str();
    iq->add_option("--pixels", o->pixels, "Image width = height at the 0.25 m GSD (the domain is one image)")
        ->capture_default_str();
    iq->add_option("--spp", o->samplesPerPixel, "Samples per pixel")->check(CLI::Range(1, 4096))->capture_default_str();
    iq->add_option("--seed", o->seed, "Random seed")->check(CLI::Range(uint64_t{0}, uint64_t{1} << 62))->capture_default_str();
    iq->add_option("--threads", o->threads, "Worker threads (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    iq->callback([o] {
        const littoral::OutputFolderLock lock(o->out);  // one command per output folder
        o->progress = !littoral::globalOptions().quiet;
        std::string summary;
        littoral::pipelines::runImageQualityStudy(*o, &summary);
        std::printf("%s", summary.c_str());
    });
}};

}  // namespace
