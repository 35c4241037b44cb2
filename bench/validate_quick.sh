#!/usr/bin/env bash
# Issue 21's benchmark: `littoral validate --quick` (docs/validation.md) as CI runs it, with its wall
# time and peak memory (GNU time) and each case's share of the wall time (from summary.json).
# Usage: bench/validate_quick.sh [OUT_DIR]   (default out/bench-validate-quick; needs build/bin/littoral)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/bench-validate-quick}"
rm -rf "$out"
/usr/bin/time -f "%e %M" -o "$out.time" "$root/build/bin/littoral" -q validate --quick --out "$out" > "$out.log" 2>&1 \
    || { cat "$out.log"; exit 1; }
read -r wall kib < "$out.time"
echo "validate --quick: $wall s wall, peak memory $((kib / 1024)) MiB"
/usr/bin/python3 - "$out/summary.json" "$wall" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
wall = float(sys.argv[2])
print("| case | category | checks | wall time (s) | share of the run |")
print("|---|---|---|---|---|")
for c in j["cases"]:
    print("| %s | %s | %d | %.1f | %.0f %% |" % (c["name"], c["category"], len(c["checks"]), c["seconds"], 100 * c["seconds"] / wall))
PY
