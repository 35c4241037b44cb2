#!/usr/bin/env bash
# Issue 9's coastal benchmark: the synthetic coastal site (data_synthetic/coastal_site/, the
# dissertation's Chapter 10 scene, nadir simulation C, 450 x 300 px; three bands over 0.4-0.7 um and
# constituent water with pure water, where the dissertation had two bands and Table 10.3 water)
# rendered at configuration C's full photon counts: 50 M surface + 70 M volume photons, search radius 0.4 m. Prints the wall
# time, CPU time and peak memory of `littoral run` (GNU time), and the photon pass's share.
# Usage: bench/coastal_full.sh [OUT_DIR]   (default out/bench-coastal-full; needs build/bin/littoral)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/bench-coastal-full}"
site="$out/site"
rm -rf "$out"
mkdir -p "$out"
cp -r "$root/data_synthetic/coastal_site" "$site"
sed -i 's/  photons: {surface: [0-9]*, volume: [0-9]*}/  photons: {surface: 50000000, volume: 70000000}/' "$site/scene.yaml"
grep -q "photons: {surface: 50000000, volume: 70000000}" "$site/scene.yaml"
/usr/bin/time -v "$root/build/bin/littoral" --stats run "$site/scene.yaml" --out "$out/render" \
  > "$out/run.log" 2> "$out/time.log" || { cat "$out/time.log"; exit 1; }
grep -E "photons: [0-9]+ photons in|photons (emitted|stored)" "$out/time.log" || true
grep -E "Elapsed \(wall|User time|System time|Maximum resident" "$out/time.log"
