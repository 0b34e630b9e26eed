#!/bin/sh
# Irradiance methods x sizes on the eight sample HDRs -> tests/bench/results/irradiance/{sweep.csv,
# benchmark.csv, error_vs_time.png}. Usage: tests/bench/irradiance_sweep.sh BUILD_DIR
# (a Release build with benchmarks; run data/fetch.sh first).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:?usage: irradiance_sweep.sh BUILD_DIR}
out="$root/tests/bench/results/irradiance"
mkdir -p "$out"
bench=$(find "$build" -name irradiance_bench -type f | head -n 1)
sweep=$(find "$build" -name irradiance_sweep -type f | head -n 1)
[ -x "$bench" ] && [ -x "$sweep" ] || { echo "build irradiance_bench and irradiance_sweep first" >&2; exit 1; }

"$bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
  --benchmark_format=csv > "$out/benchmark.csv"
"$sweep" "$out/sweep.csv" "$root"/data/cache/env/*.exr

# Error versus time, one point per (map, method setting); 1% tolerance line.
awk -F, 'NR > 1 && $4 == 32 || NR > 1 && $2 == "exact" || NR > 1 && $2 == "auto" {
  print $6 / 2, $7 * 100 > ("'"$out"'/.plot-" $2 ".dat") }' "$out/sweep.csv"
gnuplot <<GP
set terminal pngcairo size 900,600 font ",11"
set output "$out/error_vs_time.png"
set title "Diffuse irradiance cubemaps from 1024x512 maps (8 samples): error vs time"
set xlabel "time per cubemap on 2 cores (ms): process CPU time / 2"
set ylabel "relative RMS error on the sphere (%)"
set logscale xy
set grid
set key top right
set arrow from graph 0, first 1 to graph 1, first 1 nohead dt 2 lc rgb "gray40"
plot "$out/.plot-sh.dat" with points pt 7 ps 1.1 title "SH orders 2-8 (from cubemap), face 32", \
     "$out/.plot-sh-equirect.dat" with points pt 5 ps 1.1 title "SH order 2 from equirect, face 32", \
     "$out/.plot-brute.dat" with points pt 9 ps 1.1 title "brute, tolerance 0.1-5%, face 32", \
     "$out/.plot-auto.dat" with points pt 13 ps 1.3 title "auto (1%), face from content", \
     "$out/.plot-exact.dat" with points pt 3 ps 1.1 title "exact sum, face 16"
GP
rm -f "$out"/.plot-*.dat
echo "wrote $out/sweep.csv $out/benchmark.csv $out/error_vs_time.png"
