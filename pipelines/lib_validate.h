#pragma once
// `littoral validate [--quick] --out DIR`: the project's validation suite as one command
// (docs/validation.md). Each case renders or solves a scene and compares what it measures with an
// independent reference: an analytic solution, a published table (Mobley et al. 1993; Gordon and
// Ding 1992), a second estimator of the same scene, or the deterministic 1-D column solver. It
// writes DIR/report.html (a table of every check and each case's plots), DIR/summary.json (each
// check's measured value, standard error, reference, tolerance and verdict) and DIR/cases/<case>/
// (the case's scene, its run and its charts).
#include <string>
#include <vector>

namespace littoral::pipelines {

struct ValidateOptions {
    std::string out;
    bool quick = false;               // CI settings: fewer samples, the slow photon-map cases left out
    std::vector<std::string> cases;   // names to run; empty = every case of the chosen setting
    int threads = 0;
    bool progress = true;             // a line per case on stderr, with the elapsed time and an ETA
};

struct ValidateOutcome {
    int cases = 0, failedCases = 0, checks = 0, failedChecks = 0;
    double seconds = 0;
    std::string summary;  // what the command prints
};

// Runs the suite. InputError for an unknown case name (naming the known ones) before anything runs.
ValidateOutcome runValidation(const ValidateOptions& options);

// The names of every case, in the order they run, and whether --quick includes each.
struct ValidationCaseInfo {
    std::string name, category;
    bool quick;
};
std::vector<ValidationCaseInfo> validationCases();

}  // namespace littoral::pipelines
