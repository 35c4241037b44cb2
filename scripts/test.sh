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
ctest --output-on-failure -j"${LITTORAL_JOBS:-$(nproc)}" --timeout 900
echo "build + tests: $(( $(date +%s) - start )) s"
