#!/usr/bin/env bash
# Batch in one process against one process per file: N bakes of the sample bunny
# (copies named bunny_01.ply ...), as `sss-bake ALL -o DIR/` (the environment loaded and the
# ~0.2 s start-up paid once) and as N `sss-bake ONE -o FILE` processes, run after run
# alternately, median of RUNS. Wall clock and the processes' CPU time (bash's `times`).
# Usage: tests/bench/batch_bench.sh [BUILD_DIR] [N=20] [RUNS=3] [-- BAKE OPTIONS...]
#   Default bake options: the bunny as run-pipeline.sh bakes it but without shadow rays or bounces
#   and with the half-space energy (--visibility none --energy halfspace), where start-up matters
#   most; pass others after "--" (e.g. the defaults: "--").
# Output: tests/bench/results/bake/batch.csv (mode,run,bakes,wall_s,cpu_s) and batch.txt
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
positional=()
while [[ $# -gt 0 && $1 != -- ]]; do positional+=("$1"); shift; done
custom=0
[[ ${1:-} == -- ]] && { shift; custom=1; }
options=("$@")
[[ $custom == 1 ]] || options=(--visibility none --energy halfspace)
build=$(cd "${positional[0]:-$root/build}" && pwd)
n=${positional[1]:-20}
runs=${positional[2]:-3}
out=$root/tests/bench/results/bake
data=$root/data/cache
mkdir -p "$out"
[[ -f $data/meshes/bunny.ply ]] || { echo "missing sample data: run data/fetch.sh" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/in"
inputs=()
for i in $(seq -w 1 "$n"); do
  cp "$data/meshes/bunny.ply" "$tmp/in/bunny_$i.ply"
  inputs+=("$tmp/in/bunny_$i.ply")
done
bake=("$build/tools/sss-bake" -e "$data/env/forest.exr" -m marble --mm-per-unit 15 -q
  "${options[@]}")

# Seconds of wall clock and of CPU (user + system of the children) of "$@".
measure() {
  local start end cpu0 cpu1 self=$BASHPID # the children's times count once they are waited for
  cpu0=$(awk '{print $14 + $15 + $16 + $17}' "/proc/$self/stat")
  start=$(date +%s.%N)
  "$@" >/dev/null
  end=$(date +%s.%N)
  cpu1=$(awk '{print $14 + $15 + $16 + $17}' "/proc/$self/stat")
  awk -v s="$start" -v e="$end" -v c0="$cpu0" -v c1="$cpu1" -v hz="$(getconf CLK_TCK)" \
    'BEGIN {print e - s, (c1 - c0) / hz}'

}
one_process() { rm -rf "$tmp/batch" && "${bake[@]}" "${inputs[@]}" -o "$tmp/batch/"; }
processes() {
  rm -rf "$tmp/single" && mkdir -p "$tmp/single"
  for f in "${inputs[@]}"; do "${bake[@]}" "$f" -o "$tmp/single/$(basename "$f")"; done
}

echo "mode,run,bakes,wall_s,cpu_s" >"$out/batch.csv"
for run in $(seq 1 "$runs"); do
  for mode in one_process processes; do
    read -r wall cpu < <(measure "$mode")
    printf '%s,%d,%d,%.3f,%.3f\n' "$mode" "$run" "$n" "$wall" "$cpu" | tee -a "$out/batch.csv" >&2
  done
done
# The bakes must be the same either way.
for f in "${inputs[@]}"; do
  cmp -s "$tmp/batch/$(basename "$f")" "$tmp/single/$(basename "$f")" ||
    { echo "batch_bench: $(basename "$f") differs between the modes" >&2; exit 1; }
done

median() { sort -n | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
col() { awk -F, -v m="$1" -v c="$2" '$1 == m {print $c}' "$out/batch.csv" | median; }
w1=$(col one_process 4) wn=$(col processes 4) c1=$(col one_process 5) cn=$(col processes 5)
awk -v n="$n" -v runs="$runs" -v opts="${options[*]}" -v cores="$(nproc)" -v w1="$w1" \
  -v wn="$wn" -v c1="$c1" -v cn="$cn" 'BEGIN {
    printf "%d bakes of the bunny (%s), median of %d runs, %d cores\n", n, opts, runs, cores
    printf "one process:  wall %.2f s, CPU %.2f s\n", w1, c1
    printf "%d processes: wall %.2f s, CPU %.2f s\n", n, wn, cn
    printf "saved: %.2f s wall (%.3f s per bake, %.2fx), %.2f s CPU\n", wn - w1, (wn - w1) / n,
           wn / w1, cn - c1
  }' | tee "$out/batch.txt"
