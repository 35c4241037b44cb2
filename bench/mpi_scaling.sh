#!/usr/bin/env bash
# Issue 23's strong-scaling benchmark: one `littoral run` of the synthetic coastal site
# (data_synthetic/coastal_site/, its own photon counts and 450 x 300 px nadir view) as one process
# with 1 and 2 threads, and as 2 and 4 MPI ranks of one thread each. This machine has 2 cores: 4
# ranks are oversubscribed (`--oversubscribe`), so that row shows the cost of the exchanges and of
# sharing cores, not a speed-up. Every output of the other layouts is compared byte for byte with
# the one-thread output (but the IR's validity.json, which records the build's timings). Prints a Markdown table (wall time, speed-up against 1 thread, peak memory of
# the largest process) and writes OUT/strong_scaling.csv and docs/images/strong_scaling.svg.
# Usage: bench/mpi_scaling.sh [OUT_DIR]   (default out/bench-mpi-scaling; needs build/bin/littoral
# built with MPI, and mpirun)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$root/out/bench-mpi-scaling}"
bin="$root/build/bin/littoral"
rm -rf "$out"
mkdir -p "$out"
cp -r "$root/data_synthetic/coastal_site" "$out/site"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export SOURCE_DATE_EPOCH=1796256000  # the EXRs' DateTime, so that the outputs can match byte for byte
echo "ranks,threads,wall_s,max_rss_mib" > "$out/strong_scaling.csv"
run() {  # ranks threads
  local ranks=$1 threads=$2 dir="$out/r$1t$2" launch=()
  if [ "$ranks" -gt 1 ]; then launch=(mpirun -np "$ranks" --oversubscribe); fi
  /usr/bin/time -f "%e %M" -o "$out/time_r${ranks}t${threads}" "${launch[@]}" "$bin" -q run "$out/site/scene.yaml" \
    --out "$dir" --threads "$threads" > "$out/log_r${ranks}t${threads}" 2>&1
  read -r wall rss < "$out/time_r${ranks}t${threads}"
  echo "$ranks,$threads,$wall,$((rss / 1024))" >> "$out/strong_scaling.csv"
  if [ "$ranks$threads" != "11" ]; then
    (cd "$out/r1t1" && find . -type f ! -name .littoral.lock ! -name validity.json -print0 | xargs -0 -I{} cmp -s {} "$dir/{}") \
      || { echo "outputs of $ranks ranks x $threads threads differ from one process" >&2; exit 1; }
  fi
}
run 1 1
run 1 2
run 2 1
run 4 1
/usr/bin/python3 - "$out/strong_scaling.csv" "$root/docs/images/strong_scaling.svg" <<'PY'
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.DictReader(open(sys.argv[1])))
base = float(rows[0]["wall_s"])
print("| layout | wall time (s) | speed-up vs 1 thread | peak memory, largest process (MiB) |")
print("|---|---|---|---|")
for r in rows:
    name = f"{r['ranks']} rank{'s' if r['ranks'] != '1' else ''} x {r['threads']} thread{'s' if r['threads'] != '1' else ''}"
    if r["ranks"] == "4": name += " (oversubscribed: 2 cores)"
    print(f"| {name} | {float(r['wall_s']):.1f} | {base / float(r['wall_s']):.2f} | {r['max_rss_mib']} |")
fig, ax = plt.subplots(figsize=(5.5, 3.6))
workers = [int(r["ranks"]) * int(r["threads"]) for r in rows]
speed = [base / float(r["wall_s"]) for r in rows]
thr = [(w, s) for w, s, r in zip(workers, speed, rows) if r["ranks"] == "1"]
rk = [(w, s) for w, s, r in zip(workers, speed, rows) if r["threads"] == "1"]
ax.plot([p[0] for p in thr], [p[1] for p in thr], "o-", label="1 process, threads")
ax.plot([p[0] for p in rk], [p[1] for p in rk], "s--", label="MPI ranks x 1 thread")
ax.plot([1, 2], [1, 2], ":", color="grey", label="ideal (2 cores)")
ax.axvline(2, color="grey", lw=0.5)
ax.set_xlabel("workers (ranks x threads); 2 cores, 4 oversubscribed")
ax.set_ylabel("speed-up against 1 thread")
ax.set_title("Coastal site, littoral run: strong scaling")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2])
PY
