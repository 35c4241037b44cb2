#!/usr/bin/env bash
# The long fuzzing campaign recorded in docs/reliability.md: every target, one after the other
# (one process each, -jobs=1, at a lowered priority, nice LITTORAL_FUZZ_NICE = 5: the machine is
# shared; at nice 19 the worker starved for minutes at a time), RUNS executions each,
# starting from the committed seed corpora (left untouched; new inputs go to OUT/<target>/new).
# The timeout is wall-clock time per input: 120 s, because on a shared 2-core machine at load 7 a
# niced process can wait seconds for the CPU (a 3-byte input once took 6 s of wall time for 0.01 s
# of CPU); a real hang or blow-up on inputs of at most 4 KB still exceeds it by far. Inputs are at
# most 4 KiB, 16 KiB for ir_render (an IR folder: scene.json and meshes; LITTORAL_FUZZ_MAX_LEN
# overrides both). ir_render is built only with -DLITTORAL_FUZZ_RENDER=ON, so it is not in the
# default list: name it (docs/reliability.md). LITTORAL_FUZZ_SECONDS, when set, also stops each
# target after that many seconds (-max_total_time), whichever of the two limits comes first; the
# summary line records the executions reached. A target with a grown corpus committed in
# fuzz/corpus-grown/<target>.tar.xz starts from it when OUT/<target>/new is empty.
# Usage: fuzz/campaign.sh FUZZ_BUILD_DIR RUNS OUT_DIR [targets...]
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build=$1 runs=$2 out=$3
shift 3
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scene ir ply obj off stl raster soundings spectrum_csv checkpoint)
mkdir -p "$out"
for t in "${targets[@]}"; do
  dict=()
  [ -f "$root/fuzz/$t.dict" ] && dict=(-dict="$root/fuzz/$t.dict")
  max_len=4096
  [ "$t" = ir_render ] && max_len=16384
  max_len=${LITTORAL_FUZZ_MAX_LEN:-$max_len}
  time_limit=()
  [ -n "${LITTORAL_FUZZ_SECONDS:-}" ] && time_limit=(-max_total_time="$LITTORAL_FUZZ_SECONDS")
  mkdir -p "$out/$t/new" "$out/$t/artifacts"
  # A campaign spread over sessions goes on from the corpus the last one grew, committed as
  # fuzz/corpus-grown/<target>.tar.xz (the machine's own folders do not outlive a session).
  grown="$root/fuzz/corpus-grown/$t.tar.xz"
  if [ -f "$grown" ] && [ -z "$(ls -A "$out/$t/new")" ]; then
    tar -xJf "$grown" -C "$out/$t/new" --strip-components=1
    echo "$t: $(ls "$out/$t/new" | wc -l) inputs from $grown"
  fi
  start=$(date +%s)
  # -jobs=1: one worker process, whose output libFuzzer writes to fuzz-0.log in the current
  # folder, hence the cd.
  (cd "$out/$t" && nice -n "${LITTORAL_FUZZ_NICE:-5}" /usr/bin/time -f "%e s wall, %U s user, %S s system" \
     -o "$out/$t/time.txt" "$build/fuzz_$t" -runs="$runs" -jobs=1 -timeout=120 -rss_limit_mb=2048 \
     -max_len="$max_len" -print_final_stats=1 -artifact_prefix="$out/$t/artifacts/" "${dict[@]}" "${time_limit[@]}" \
     "$out/$t/new" "$root/fuzz/corpus/$t" > "$out/$t/driver.txt" 2>&1)
  rc=$?
  log="$out/$t/fuzz-0.log"
  echo "$t rc=$rc seconds=$(( $(date +%s) - start )) $(grep -E '^stat::number_of_executed_units' "$log")" \
       "$(grep -cE 'ERROR|SUMMARY' "$log") error line(s), artifacts: $(ls "$out/$t/artifacts" | tr '\n' ' ')" \
       "$(grep -E '^stat::slowest_unit_time_sec' "$log") ($(cat "$out/$t/time.txt"))" \
    | tee -a "$out/summary.txt"
done
