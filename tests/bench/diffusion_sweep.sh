#!/bin/sh
# Diffusion sums on the dragons (methods x tolerances, median of 3 runs) and the resolution study
# on spheres -> tests/bench/results/diffusion/{benchmark.csv,sweep.csv,resolution.csv,
# error_vs_time.png,time_vs_n.png,resolution.png}. Usage: tests/bench/diffusion_sweep.sh BUILD_DIR
# (a Release build with benchmarks; run data/fetch.sh first). Takes several minutes on 2 cores.
# SKIP_RUN=1 redraws the charts from the existing benchmark.csv and resolution.csv.
# Charts show process CPU time (both threads): on a shared machine wall time measures the load;
# on an idle 2-core machine the wall time is about half the CPU time (static chunks, no locks).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:?usage: diffusion_sweep.sh BUILD_DIR}
out="$root/tests/bench/results/diffusion"
mkdir -p "$out"
bench=$(find "$build" -name diffusion_bench -type f | head -n 1)
resolution=$(find "$build" -name diffusion_resolution -type f | head -n 1)
[ -x "$bench" ] && [ -x "$resolution" ] || {
  echo "build diffusion_bench and diffusion_resolution first" >&2
  exit 1
}

if [ "${SKIP_RUN:-0}" != 1 ]; then
  "$bench" --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
    --benchmark_format=csv > "$out/benchmark.csv"
  "$resolution" > "$out/resolution.csv"
fi

# Medians only, one clean row per case. Google Benchmark's CSV: name and label quoted (a label
# may hold commas), then the numbers and the counters by name.
awk -F, '
  NR == 1 { gsub(/"/, ""); for (i = 1; i <= NF; i++) col[$i] = i; next }
  $1 ~ /_median"$/ {
    name = $1; gsub(/"/, "", name); split(name, part, "/")
    line = $0; gsub(/"[^"]*"/, "Q", line); split(line, f, ",")
    printf "%s,%s,%s,%d,%d,%.0f,%.1f,%.1f,%.5f,%.5f,%d\n", part[1], part[2], part[3],
      f[col["vertices"]], f[col["gaussians"]], f[col["interactions"]], f[col["real_time"]],
      f[col["cpu_time"]], f[col["error"]], f[col["estimated_error"]], f[col["ran_hierarchical"]]
  }' "$out/benchmark.csv" |
  { echo "mesh,method,tolerance,vertices,gaussians,interactions,wall_ms,cpu_ms,error,estimated_error,ran_hierarchical"; cat; } \
  > "$out/sweep.csv"

# Error versus time: one series per method, all meshes and tolerances.
for m in gauss hierarchical incremental auto exact; do
  awk -F, -v m="$m" 'NR > 1 && $2 == m { print $8, $9 * 100, $1 }' "$out/sweep.csv" \
    > "$out/.plot-$m.dat"
done
# Time versus N at 1%.
for m in gauss hierarchical incremental auto; do
  awk -F, -v m="$m" 'NR > 1 && $2 == m && $3 == 0.01 { print $4, $8 }' "$out/sweep.csv" \
    | sort -n > "$out/.n-$m.dat"
done
for m in exact gauss hierarchical incremental; do
  for mat in marble skin1; do
    awk -F, -v m="$m" -v mat="$mat" 'NR > 1 && $6 == m && $1 == mat { print $5, $7 * 100 }' \
      "$out/resolution.csv" > "$out/.res-$mat-$m.dat"
  done
done
gnuplot <<GP
set terminal pngcairo size 900,600 font ",11"
set grid
set termoption noenhanced
set output "$out/error_vs_time.png"
set title "Diffusion sums on the 150 mm dragon (5K-437K vertices, marble): error vs time"
set xlabel "CPU time, both threads (ms, median of 3; includes the Gaussian fit)"
set ylabel "relative RMS error of B vs gauss at 0.1% (%)"
set logscale xy
set key top right
plot "$out/.plot-gauss.dat" using 1:2 with points pt 7 ps 1.2 title "gauss", \
     "$out/.plot-hierarchical.dat" using 1:2 with points pt 5 ps 1.2 title "hierarchical", \
     "$out/.plot-incremental.dat" using 1:2 with points pt 9 ps 1.2 title "incremental", \
     "$out/.plot-auto.dat" using 1:2 with points pt 6 ps 2 title "auto", \
     "$out/.plot-exact.dat" using 1:2 with points pt 3 ps 1.5 title "exact (res4 only)"
set output "$out/time_vs_n.png"
set title "Diffusion sums at 1% tolerance: time vs vertices (dragon, marble)"
set xlabel "vertices"
set ylabel "CPU time, both threads (ms)"
set key top left
plot "$out/.n-gauss.dat" with linespoints pt 7 title "gauss", \
     "$out/.n-hierarchical.dat" with linespoints pt 5 title "hierarchical", \
     "$out/.n-incremental.dat" with linespoints pt 9 title "incremental", \
     "$out/.n-auto.dat" with linespoints pt 6 title "auto"
set output "$out/resolution.png"
set title "20 mm sphere, smooth light: error vs mesh spacing (reference: 40962 vertices)"
set xlabel "vertex spacing / smallest transport mean free path 1/sigma_t'"
set ylabel "relative RMS error of B (%)"
set key top left
plot "$out/.res-marble-exact.dat" with linespoints pt 3 title "marble exact", \
     "$out/.res-marble-gauss.dat" with linespoints pt 7 title "marble gauss", \
     "$out/.res-marble-incremental.dat" with linespoints pt 9 title "marble incremental", \
     "$out/.res-skin1-exact.dat" with linespoints pt 3 dt 2 title "skin1 exact", \
     "$out/.res-skin1-gauss.dat" with linespoints pt 7 dt 2 title "skin1 gauss", \
     "$out/.res-skin1-incremental.dat" with linespoints pt 9 dt 2 title "skin1 incremental"
GP
rm -f "$out"/.plot-*.dat "$out"/.n-*.dat "$out"/.res-*.dat
echo "wrote $out/sweep.csv $out/resolution.csv $out/*.png"
