#!/usr/bin/env bash
# Fresh-machine command 2 (and CI): install dependencies, build everything, run the whole test
# suite with CTest. Exits non-zero if any test fails.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
start=$(date +%s)
bash "$root/scripts/build.sh"
built=$(date +%s)
echo "build: $((built - start)) s"
cd "$root/build"
# A fresh build directory has no test timings, and CTest would then start the longest tests (the
# validation suite, the photon-map columns) in index order, some of them last, alone on one core.
# Seed it with the timings of a clean CI run (tests/ctest_costs.txt: the tests of 10 s or more),
# so that they start first; CTest keeps its own measurements from then on.
if [ ! -f Testing/Temporary/CTestCostData.txt ]; then
  mkdir -p Testing/Temporary
  cp "$root/tests/ctest_costs.txt" Testing/Temporary/CTestCostData.txt
fi
ctest --output-on-failure -j"${LITTORAL_JOBS:-$(nproc)}" --timeout 900
echo "build + tests: $(( $(date +%s) - start )) s"
