#!/usr/bin/env bash
# Process start-up: the user CPU time of `littoral --version` and of a test process that runs no
# test, side by side with an empty program linked against OpenImageIO (compiled here), which is
# what every Littoral process paid before OpenImageIO became a plugin loaded on the first image
# (core/image_io.h; docs/performance.md, "Process start-up"). Mean of N runs each, interleaved.
# Usage: bench/startup.sh [BUILD_DIR] [N]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=${1:-$root/build} n=${2:-20}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo 'int main() { return 0; }' > "$tmp/empty.cpp"
g++ "$tmp/empty.cpp" -o "$tmp/empty_oiio" -Wl,--no-as-needed -lOpenImageIO -lOpenImageIO_Util
g++ "$tmp/empty.cpp" -o "$tmp/empty"
declare -A cmd=(
  [empty]="$tmp/empty"
  [empty_linked_to_oiio]="$tmp/empty_oiio"
  [littoral_version]="$build/bin/littoral --version"
  [test_pipelines_no_test]="$build/tests/test_pipelines --gtest_filter=NoSuchTest"
)
declare -A total
for k in "${!cmd[@]}"; do total[$k]=0; done
for ((i = 0; i < n; ++i)); do
  for k in "${!cmd[@]}"; do
    # user + system CPU seconds of one run (GNU time), summed over runs
    /usr/bin/time -o "$tmp/t" -f "%U %S" ${cmd[$k]} > /dev/null 2>&1
    t=$(awk '{print $1 + $2}' "$tmp/t")
    total[$k]=$(awk -v a="${total[$k]}" -v b="$t" 'BEGIN {print a + b}')
  done
done
printf "%-26s %s\n" "process" "CPU s per start (mean of $n)"
for k in empty empty_linked_to_oiio littoral_version test_pipelines_no_test; do
  printf "%-26s %.3f\n" "$k" "$(awk -v a="${total[$k]}" -v n="$n" 'BEGIN {print a / n}')"
done
