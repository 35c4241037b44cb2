#!/usr/bin/env bash
# Renders a fixed set of the project's shipped scenes and prints one SHA-256 line per numeric
# output (radiance EXR/ENVI, truth images, probe tables, wave meshes and statistics, the IR), so
# that a refactoring can be shown to change no result: run it before and after, then diff.
#
#   scripts/golden_outputs.sh [--quick] BUILD_DIR OUT_DIR > hashes.txt
#   diff before.txt after.txt        # empty: every listed output is identical to the byte
#
# --quick skips the two slowest runs (the photon-map Mobley problems, about 80 s together).
# Files whose contents name the run (timings, paths, dates: run.json, validity.json, logs and the
# PNG previews, which carry no numbers the EXR does not) are left out of the list. Needs oiiotool
# (openimageio-tools, which scripts/setup-deps.sh installs).
set -euo pipefail
quick=0
if [[ "${1:-}" == "--quick" ]]; then quick=1; shift; fi
build="${1:?usage: golden_outputs.sh [--quick] BUILD_DIR OUT_DIR}"
out="${2:?usage: golden_outputs.sh [--quick] BUILD_DIR OUT_DIR}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="$build/bin/littoral"
rm -rf "$out"
mkdir -p "$out"
scenes=(
  mobley1993/problem1_albedo09 mobley1993/problem1_albedo02 mobley1993/problem6
  demos/glint_2ms demos/glint_10ms demos/pool_caustics demos/floating_cube
)
if [[ $quick == 0 ]]; then
  scenes+=(mobley1993/problem1_albedo09_photon_maps mobley1993/problem6_photon_maps)
fi
for s in "${scenes[@]}"; do
  name="${s//\//_}"
  "$bin" --quiet run "$root/data_synthetic/$s.yaml" --out "$out/$name" >/dev/null
done
"$bin" --quiet demo --out "$out/demo" >/dev/null
mkdir -p "$out/waves"
"$bin" --quiet waves --wind 6 --size 20 --spacing 0.25 --triangles 4000 --seed 7 --out "$out/waves/waves.ply" --stats "$out/waves/stats.json" >/dev/null
cd "$out"
# EXR files carry their creation time and JSON files their timings: both are hashed without them
# (an EXR is hashed as oiiotool's listing of its attributes, but the DateTime, and its pixels'
# SHA-1).
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
find . -type f \( -name '*.exr' -o -name '*.img' -o -name '*.csv' -o -name '*.ply' -o -name 'scene.json' \
  -o -name 'probes.json' -o -name '*stats*.json' \) -print0 | sort -z | while IFS= read -r -d '' f; do
  case "$f" in
    *.exr)
      oiiotool --info -v --hash "$f" | grep -v -e DateTime -e '^Reading' > "$tmp/x.txt"
      echo "$(sha256sum < "$tmp/x.txt" | cut -d' ' -f1)  $f" ;;
    *.json)
      /usr/bin/python3 -c 'import json, sys
def strip(v):
    if isinstance(v, dict): return {k: strip(x) for k, x in v.items() if k not in ("timing_s", "seconds")}
    if isinstance(v, list): return [strip(x) for x in v]
    return v
print(json.dumps(strip(json.load(open(sys.argv[1]))), sort_keys=True))' "$f" > "$tmp/x.json"
      echo "$(sha256sum < "$tmp/x.json" | cut -d' ' -f1)  $f" ;;
    *) sha256sum "$f" ;;
  esac
done
