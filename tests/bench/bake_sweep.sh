#!/usr/bin/env bash
# The whole-bake benchmark and sweep (issue 3): the 100K-vertex dragon against the 5 s / 1 GB
# target (bake_bench, median of 5; peak memory of the sss-bake process by /usr/bin/time), then
# methods x tolerances on the four dragon resolutions (bake_sweep) and the charts.
# Usage: tests/bench/bake_sweep.sh [BUILD_DIR] [--charts-only]
#   BUILD_DIR: default build (Release, benchmarks on); --charts-only redraws from the CSV files.
# Output: docs/bake/: bake_bench.csv, bake_memory.txt, bake_sweep.csv, bake_visibility.csv,
#   error_vs_time.png, time_vs_n.png, visibility_noise.png
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=$root/docs/bake
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
  -m marble --size-mm 150 --threads 2 -q -o "$tmp/dragon.ply" --json "$tmp/dragon.json" \
  2> "$tmp/time.txt"
{
  grep -E "Maximum resident set size|Elapsed \(wall clock\)|User time|System time" "$tmp/time.txt"
  echo "stages (s): $(tr -d ' \n' < "$tmp/dragon.json" | grep -o '"stages":{[^}]*}')"
} | tee "$out/bake_memory.txt"

echo "== bake_sweep" >&2
"$build/tests/bench/bake_sweep" --out "$out/bake_sweep.csv" --threads 2 \
  dragon_res4 dragon_res3 dragon_res2 dragon
"$build/tests/bench/bake_sweep" --visibility-out "$out/bake_visibility.csv" --threads 2 \
  dragon_res4 dragon_res3
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
set title "visibility noise: rays per vertex vs relative RMS error against 1024 rays (forest)"
set logscale xy
set xlabel "rays per vertex"
set ylabel "relative RMS error"
set key right top
plot for [d in "dragon_res4 dragon_res3"] "$out/bake_visibility.csv" \
       using (strcol(1) eq d ? \$3 : 1/0):5 with linespoints title "E ".d, \
     for [d in "dragon_res4 dragon_res3"] "$out/bake_visibility.csv" \
       using (strcol(1) eq d ? \$3 : 1/0):6 with linespoints title "B (marble) ".d
GNUPLOT
echo "wrote $out" >&2
