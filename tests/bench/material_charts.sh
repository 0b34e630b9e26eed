#!/bin/sh
# Regenerates tests/bench/results/material: fits.csv (every preset x profile x tolerance: totals, K,
# error, fit time), profile_<material>.csv (2 pi r^2 R_d(r) of each profile and its 1% Gaussian fit)
# and profiles.png. Usage: tests/bench/material_charts.sh BUILD_DIR
set -eu
build=${1:?usage: material_charts.sh BUILD_DIR}
root=$(cd "$(dirname "$0")/../.." && pwd)
out="$root/tests/bench/results/material"
mkdir -p "$out"
"$build/tests/bench/material_profiles" "$out"
gnuplot <<GNUPLOT
set terminal pngcairo size 1500,480 font ",11"
set output "$out/profiles.png"
set datafile separator ","
set multiplot layout 1,3 title "Energy per unit ln r, 2{/Symbol p} r^2 R_d(r) (red channel), and the 1% Gaussian fits (dashed)"
set logscale x
set format x "10^{%L}"
set xlabel "r (mm)"
set ylabel "2{/Symbol p} r^2 R_d(r)"
set key top right
do for [m in "marble skin1 ketchup"] {
  set title m
  plot "$out/profile_".m.".csv" using 1:2 skip 1 with lines lw 2 lc rgb "#1f77b4" title "dipole", \
       "" using 1:5 skip 1 with lines dt 2 lw 2 lc rgb "#1f77b4" notitle, \
       "" using 1:8 skip 1 with lines lw 2 lc rgb "#d62728" title "beam", \
       "" using 1:11 skip 1 with lines dt 2 lw 2 lc rgb "#d62728" notitle, \
       "" using 1:14 skip 1 with lines lw 2 lc rgb "#2ca02c" title "burley", \
       "" using 1:17 skip 1 with lines dt 2 lw 2 lc rgb "#2ca02c" notitle
}
unset multiplot
GNUPLOT
echo "wrote $out"
