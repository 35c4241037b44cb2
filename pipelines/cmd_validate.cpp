// `littoral validate [--quick] --out DIR [--case NAME ...]`: the validation suite (analytic,
// published, solver against solver, 3-D against 1-D) with report.html and summary.json;
// docs/validation.md. Exit 1 if any case fails.
#include <cstdio>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "core/atomic_file.h"
#include "pipelines/command_registry.h"
#include "pipelines/lib_validate.h"

namespace {

littoral::CommandRegistrar registerValidate{"validate", [](CLI::App& app) {
    auto* cmd = app.add_subcommand("validate", "Run the validation suite and write report.html and summary.json (exit 1 on a failure)");
    auto o = std::make_shared<littoral::pipelines::ValidateOptions>();
    cmd->add_option("--out", o->out, "Output folder (report.html, summary.json, cases/, runs/)")->required();
    cmd->add_flag("--quick", o->quick, "CI settings: fewer samples, the slow photon-map cases left out");
    std::string names;
    for (const auto& c : littoral::pipelines::validationCases()) names += (names.empty() ? "" : ", ") + c.name;
    cmd->add_option("--case", o->cases, "Run only these cases: " + names);
    cmd->add_option("--threads", o->threads, "Worker threads (0 = all cores; at most 1024)")->check(CLI::Range(0, 1024));
    cmd->callback([o] {
        const littoral::OutputFolderLock lock(o->out);  // one command per output folder
        o->progress = !littoral::globalOptions().quiet;
        const auto r = littoral::pipelines::runValidation(*o);
        std::printf("%s", r.summary.c_str());
        if (r.failedCases > 0) littoral::setExitCode(1);
    });
}};

}  // namespace
