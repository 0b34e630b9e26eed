#!/usr/bin/env bash
# The whole-bake benchmark and sweep: the 100K-vertex dragon against the 5 s / 1 GB
# target (bake_bench, median of 5; peak memory of the sss-bake process by /usr/bin/time), then
# methods x tolerances on the four dragon resolutions (bake_sweep) and the charts.
# Usage: tests/bench/bake_sweep.sh [BUILD_DIR] [--charts-only]
#   BUILD_DIR: default build (Release, benchmarks on); --charts-only redraws from the CSV files.
# Output: tests/bench/results/bake/: bake_bench.csv, bake_memory.txt, bake_sweep.csv,
#   bake_visibility.csv, error_vs_time.png, time_vs_n.png, visibility_noise.png
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=$root/tests/bench/results/bake
data=$root/data/cache
mkdir -p "$out"
[[ -f $data/meshes/dragon_res2.ply ]] || { echo "missing sample data: run data/fetch.sh" >&2; exit 1; }

if [[ ${2:-} != --charts-only ]]; then
echo "== bake_bench (median of 5)" >&2
"$build/tests/bench/bake_bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_out="$out/bake_bench.csv" --benchmark_out_format=csv

echo "== peak memory of sss-bake on dragon_res2" >&2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
/usr/bin/time -v "$build/tools/sss-bake" "$data/meshes/dragon_res2.ply" -e "$data/env/forest.exr" \
  -m marble --size-mm 150 --samples 64 --threads 2 -q -o "$tmp/dragon.ply" --json "$tmp/dragon.json" \
  2> "$tmp/time.txt"
{
  grep -E "Maximum resident set size|Elapsed \(wall clock\)|User time|System time" "$tmp/time.txt"
  echo "stages (s): $(tr -d ' \n' < "$tmp/dragon.json" | grep -o '"stages":{[^}]*}')"
} | tee "$out/bake_memory.txt"

echo "== bake_sweep" >&2
"$build/tests/bench/bake_sweep" --out "$out/bake_sweep.csv" --threads 2 \
  dragon_res4 dragon_res3 dragon_res2 dragon
# Visibility noise and the pilot's prediction (auto samples): the dragons and a 30 mm icosphere
# (2562 vertices) under forest and studio, each against 4096 rays.
"$build/tests/bench/bake_sweep" --visibility-out "$tmp/vis_dragons.csv" --threads 2 \
  dragon_res4 dragon_res3
python3 - "$tmp/sphere.ply" <<'PY'
import math, sys
t = (1 + 5 ** 0.5) / 2
v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
     (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
     (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
     (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
for _ in range(4):
    cache, nf = {}, []
    def mid(a, b):
        k = (min(a, b), max(a, b))
        if k not in cache:
            p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
            n = math.sqrt(sum(x * x for x in p))
            v.append(tuple(x / n for x in p))
            cache[k] = len(v) - 1
        return cache[k]
    for a, b, c in f:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    f = nf
with open(sys.argv[1], "w") as o:
    o.write(f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {len(f)}\nproperty list uchar int vertex_indices\n"
            "end_header\n")
    o.writelines("%f %f %f\n" % p for p in v)
    o.writelines(f"3 {a} {b} {c}\n" for a, b, c in f)
PY
for env in forest studio; do
  "$build/tests/bench/bake_sweep" --visibility-out "$tmp/vis_sphere_$env.csv" --threads 2 \
    --env $env --size-mm 30 "$tmp/sphere.ply"
done
{ cat "$tmp/vis_dragons.csv"; tail -q -n +2 "$tmp"/vis_sphere_*.csv | sed 's|^[^,]*sphere.ply|sphere|'; } \
  > "$out/bake_visibility.csv"
fi

gnuplot <<GNUPLOT
set datafile separator ","
set terminal pngcairo size 900,600 noenhanced
set output "$out/error_vs_time.png"
set terminal pngcairo size 1000,800 noenhanced
set multiplot layout 2,2 title "sss-bake, dragon (marble, 150 mm, forest, 64 rays/vertex, 2 threads): error of B vs diffusion time\n(tolerances 3%, 1%, 0.3%; reference: exact for res4/res3, auto at 0.1% for res2/full)"
set logscale xy
set xlabel "diffusion time (s)"
set ylabel "relative RMS error of B"
set key top right
set grid
do for [d in "dragon_res4 dragon_res3 dragon_res2 dragon"] {
  set title d
  plot for [m in "gauss incremental hierarchical auto"] "$out/bake_sweep.csv" \
    using (strcol(3) eq m && strcol(1) eq d ? \$6 : 1/0):10 with linespoints title m
}
unset multiplot
set terminal pngcairo size 900,600 noenhanced
set output "$out/time_vs_n.png"
set xlabel "vertices"
set ylabel "seconds"
set key left top
set title "whole bake time vs vertices (dragons, marble, forest, 64 rays, diffusion at 1%, 2 threads)"
plot for [m in "gauss incremental hierarchical auto"] "$out/bake_sweep.csv" \
       using (strcol(3) eq m && \$5 == 0.01 ? \$2 : 1/0):9 with linespoints title m." (bake)", \
     "$out/bake_sweep.csv" using (strcol(3) eq "auto" && \$5 == 0.01 ? \$2 : 1/0):7 \
       with linespoints title "visibility (64 rays)", \
     "$out/bake_sweep.csv" using (strcol(3) eq "exact" ? \$2 : 1/0):6 with points title "exact diffusion"
set output "$out/visibility_noise.png"
set title "visibility noise in B (marble): measured against 4096 rays (points) and predicted by the pilot (lines)"
set logscale xy
set xlabel "rays per vertex"
set ylabel "relative RMS error of B"
set key right top
plot for [d in "dragon_res4,forest dragon_res3,forest sphere,forest sphere,studio"] \
       "$out/bake_visibility.csv" using (strcol(1).",".strcol(2) eq d ? \$4 : 1/0):7 \
       with points pt 7 title d." measured", \
     for [d in "dragon_res4,forest dragon_res3,forest sphere,forest sphere,studio"] \
       "$out/bake_visibility.csv" using (strcol(1).",".strcol(2) eq d ? \$4 : 1/0):11 \
       with lines title d." predicted"
GNUPLOT
echo "wrote $out" >&2
