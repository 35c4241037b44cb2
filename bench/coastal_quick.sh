#!/usr/bin/env bash
# Issue 21's benchmark: every coastal configuration A-J (`littoral coastal X`, docs/coastal.md) at
# quick settings, one after another in one run of this script, with its wall time and peak
# memory (GNU time); H counts both of its renders (with and without photon maps). The ratio column
# is each wall time over C's, the dissertation's reference configuration.
# Usage: bench/coastal_quick.sh [OUT_DIR]   (default out/bench-coastal-quick; needs build/bin/littoral)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/bench-coastal-quick}"
rm -rf "$out"
mkdir -p "$out"
for c in A B C D E F G H I J; do
    /usr/bin/time -f "%e %M" -o "$out/$c.time" "$root/build/bin/littoral" -q coastal "$c" --out "$out/$c" \
        > "$out/$c.log" 2>&1 || { cat "$out/$c.log"; exit 1; }
done
ref=$(cut -d' ' -f1 "$out/C.time")
echo "| configuration | wall time (s) | peak memory (MiB) | wall / C |"
echo "|---|---|---|---|"
for c in A B C D E F G H I J; do
    read -r wall kib < "$out/$c.time"
    awk -v c="$c" -v w="$wall" -v k="$kib" -v r="$ref" 'BEGIN { printf "| %s | %.1f | %.0f | %.2f |\n", c, w, k / 1024, w / r }'
done
