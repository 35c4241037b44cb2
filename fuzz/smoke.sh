#!/usr/bin/env bash
# One fuzz target for a fixed time, starting from its committed seed corpus (read only: new inputs
# go to WORK/new). Exits non-zero if libFuzzer finds a crash, leak, timeout or out-of-memory; the
# input that caused it is left in WORK/artifacts/.
# Usage: fuzz/smoke.sh FUZZER CORPUS_DIR WORK_DIR SECONDS [extra libFuzzer flags...]
set -euo pipefail
fuzzer=$1 corpus=$2 work=$3 seconds=$4
shift 4
rm -rf "$work"
mkdir -p "$work/new" "$work/artifacts"
exec "$fuzzer" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
  -artifact_prefix="$work/artifacts/" "$@" "$work/new" "$corpus"
