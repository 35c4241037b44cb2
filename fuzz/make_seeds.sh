#!/usr/bin/env bash
# Makes the committed seed corpora of fuzz_ir_render and fuzz_checkpoint from the scenes in
# fuzz/seeds/ with a built `littoral`:
#   fuzz/corpus/ir_render/<scene>   each scene's IR (`littoral build`), packed (fuzz/pack.sh)
#   fuzz/corpus/checkpoint/<name>   checkpoints of the fixed run of fuzz_checkpoint
#                                   (seeds/checkpoint_run.yaml), copied while `littoral render`
#                                   runs its 3 passes: after pass 1 and 2, for every sensor and
#                                   for --sensor side
# Prints the checkpoints' ir_hash, which fuzz_checkpoint.cpp's kIrHash must equal.
# Usage: fuzz/make_seeds.sh LITTORAL_BINARY WORK_DIR
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
littoral=$1 work=$2
rm -rf "$work"
mkdir -p "$work" "$root/fuzz/corpus/ir_render" "$root/fuzz/corpus/checkpoint"
cp "$root/fuzz/seeds/cube.obj" "$work/"
for s in small surface_pm medium_pm periodic_path dielectric; do
  cp "$root/fuzz/seeds/$s.yaml" "$work/"
  "$littoral" -q build "$work/$s.yaml" --out "$work/$s"
  rm -f "$work/$s/validity.json"
  # scene.json without its indentation (the same document, half the bytes: seeds stay < 4 KB)
  python3 -c 'import json, sys; d = json.load(open(sys.argv[1])); open(sys.argv[1], "w").write(json.dumps(d, separators=(",", ":")) + "\n")' \
    "$work/$s/scene.json"
  "$root/fuzz/pack.sh" "$work/$s" > "$root/fuzz/corpus/ir_render/$s"
done

# Copies OUT/progressive.checkpoint as soon as its state.json says `passes_done: N`.
grab() {
  local out=$1 n=$2 name=$3
  for _ in $(seq 1 6000); do
    if grep -q "\"passes_done\": $n" "$out/progressive.checkpoint/state.json" 2>/dev/null; then
      cp -r "$out/progressive.checkpoint" "$work/$name"
      "$root/fuzz/pack.sh" "$work/$name" > "$root/fuzz/corpus/checkpoint/$name"
      return 0
    fi
    sleep 0.01
  done
  echo "no checkpoint after pass $n in $out" >&2
  return 1
}
cp "$root/fuzz/seeds/checkpoint_run.yaml" "$work/"
"$littoral" -q build "$work/checkpoint_run.yaml" --out "$work/checkpoint_ir"
"$littoral" -q render "$work/checkpoint_ir" --out "$work/ck_all" --threads 1 &
grab "$work/ck_all" 1 all_after_1
grab "$work/ck_all" 2 all_after_2
wait
"$littoral" -q render "$work/checkpoint_ir" --out "$work/ck_side" --sensor side --threads 1 &
grab "$work/ck_side" 1 side_after_1
wait
grep -h '"ir_hash"' "$work"/all_after_1/state.json
