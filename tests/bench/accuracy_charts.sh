#!/usr/bin/env bash
# Draws the accuracy charts from tests/bench/results/accuracy/{scenes,halfspace}.csv
# (accuracy_study output).
#   tests/bench/accuracy_charts.sh [DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
dir=${1:-$root/tests/bench/results/accuracy}
scenes=$(tail -n +2 "$dir/scenes.csv" | cut -d, -f1 | sort -u)
for scene in $scenes; do
  gnuplot <<GP
set terminal pngcairo size 900,600 font ",11"
set output "$dir/error_vs_time_$scene.png"
set datafile separator ","
set title "$scene: radiance error against the Monte Carlo reference vs bake time"
set xlabel "bake time (visibility + diffusion), s"
set ylabel "relative RMS error of L_o (noise-corrected)"
set logscale x
set key outside right top
set grid
sel(p, m) = (strcol(1) eq "$scene" && strcol(3) eq p && strcol(4) eq m)
plot for [p in "dipole beam burley"] for [m in "exact gauss incremental hierarchical auto exact-guard exact+escape"] \
  "$dir/scenes.csv" using (sel(p, m) ? \$11 : NaN):(sel(p, m) ? \$12 : NaN) \
  with points pt (p eq "dipole" ? 7 : p eq "beam" ? 5 : 9) ps 1.3 \
  lc (m eq "exact" ? 1 : m eq "gauss" ? 2 : m eq "incremental" ? 3 : m eq "hierarchical" ? 4 : m eq "auto" ? 6 : m eq "exact-guard" ? 7 : 8) \
  title p." ".m, \
  "$dir/scenes.csv" using (sel("auto", "bake-auto") ? \$11 : NaN):(sel("auto", "bake-auto") ? \$12 : NaN) \
  with points pt 3 ps 2 lw 2 lc rgb "black" title "sss-bake auto (energy, profile, method)"
GP
done
gnuplot <<GP
set terminal pngcairo size 900,600 font ",11"
set output "$dir/halfspace.png"
set datafile separator ","
set title "Half-space total diffuse reflectance (eta 1.3, 11 presets x RGB): profile / Monte Carlo"
set xlabel "1 - reduced albedo alpha'"
set ylabel "profile total / Monte Carlo total (all orders)"
set logscale x
set format x "10^{%T}"
set key left top
set grid
plot 1 with lines lc rgb "gray60" notitle, \
     "$dir/halfspace.csv" using (1-\$3):(\$8/\$4):(\$8*\$5/\$4**2) with yerrorbars pt 4 lc 1 title "dipole", \
     "" using (1-\$3):(\$9/\$4):(\$9*\$5/\$4**2) with yerrorbars pt 8 lc 2 title "beam (= burley total)", \
     "" using (1-\$3):(\$6/\$4) with points pt 7 ps 0.7 lc rgb "gray40" title "Monte Carlo multiple scattering only"
GP
# Summary tables (markdown): the error of each profile per scene, and whether auto met its
# tolerance (relative RMS of B against the same profile's exact sum) at the lowest cost.
awk -F, '
  NR == 1 { next }
  $4 == "exact" { ex[$1 "," $3] = $12; exT[$1 "," $3] = $11; noise[$1] = $14; bias[$1 "," $3] = $18; shape[$1 "," $3] = $19 }
  $4 == "auto" && $6 == 0.01 { au[$1 "," $3] = $12; auT[$1 "," $3] = $11; auM[$1 "," $3] = $5 }
  $4 == "exact-guard" { gu[$1 "," $3] = $12; guT[$1 "," $3] = $11; drop[$1] = $17 }
  $4 == "exact-noguard" { ng[$1 "," $3] = $12 }
  $4 == "exact+escape" { es[$1 "," $3] = $12; esT[$1 "," $3] = $11; esBias[$1 "," $3] = $18 }
  $4 == "bake-auto" && $6 == 0.01 { ba[$1] = $12; baT[$1] = $11; baM[$1] = $5 "/" $20 }
  !($1 in seen) { seen[$1] = 1; order[++n] = $1 }
  END {
    print "| scene | reference noise | profile | exact: err (s) | exact: energy bias, shape err | exact + escape energy: err (s), bias | auto 1%: err (s, method) | exact, no disc, no guard: err | same + guard: err (s, pairs dropped) |"
    print "|---|---|---|---|---|---|---|---|---|"
    split("dipole beam burley", profiles, " ")
    for (i = 1; i <= n; ++i) for (j = 1; j <= 3; ++j) {
      k = order[i] "," profiles[j]
      printf "| %s | %.3f | %s | %.3f (%.2f) | %+.3f, %.3f | %.3f (%.2f), %+.3f | %.3f (%.2f, %s) | %.3f | %.3f (%.2f, %.0f%%) |\n", \
        order[i], noise[order[i]], profiles[j], ex[k], exT[k], bias[k], shape[k], es[k], esT[k], esBias[k], au[k], auT[k], auM[k], ng[k], gu[k], guT[k], 100 * drop[order[i]]
    }
    print ""
    print "Best configuration against the classic dipole (exact sum, half-space energy), and sss-bake auto at 1%:"
    print ""
    print "| scene | classic dipole: err (s) | best: config, err (s) | best / dipole: error, time | sss-bake auto 1%: err (s, profile/method/energy) | auto / dipole: error, time |"
    print "|---|---|---|---|---|---|"
    for (i = 1; i <= n; ++i) {
      s = order[i]; d = ex[s ",dipole"]; dT = exT[s ",dipole"]; best = d; bestT = dT; bestC = "dipole exact"
      for (j = 1; j <= 3; ++j) {
        k = s "," profiles[j]
        if (ex[k] < best) { best = ex[k]; bestT = exT[k]; bestC = profiles[j] " exact" }
        if (es[k] < best) { best = es[k]; bestT = esT[k]; bestC = profiles[j] " exact + escape" }
      }
      printf "| %s | %.3f (%.3f) | %s, %.3f (%.3f) | %.2fx, %.1fx | %.3f (%.3f, %s) | %.2fx, %.1fx |\n", s, d, dT, bestC, best, bestT, best / d, bestT / dT, ba[s], baT[s], baM[s], ba[s] / d, baT[s] / dT
    }
  }' "$dir/scenes.csv" > "$dir/summary.md"
{
echo "| scene | profile | tolerance | auto: error vs exact (diffusion s, method) | cheapest measured config meeting it |"
echo "|---|---|---|---|---|"
awk -F, '
  NR == 1 { next }
  $4 == "gauss" || $4 == "incremental" || $4 == "hierarchical" {
    k = $1 "," $3 "," $6
    if ($16 <= $6 && (!(k in best) || $10 < best[k])) { best[k] = $10; bestM[k] = $4 }
  }
  $4 == "auto" { k = $1 "," $3 "," $6; au[k] = $16; auT[k] = $10; auM[k] = $5; keys[k] = 1 }
  END {
    for (k in keys) {
      split(k, f, ",")
      printf "| %s | %s | %s | %.4f (%.3f, %s)%s | %s |\n", f[1], f[2], f[3], au[k], auT[k], auM[k], \
        (au[k] <= f[3] ? "" : " **missed**"), (k in best ? sprintf("%s %.3f s", bestM[k], best[k]) : "none")
    }
  }' "$dir/scenes.csv" | sort
echo
echo "sss-bake's own choice (energy model, profile, method): error against the exact sum of the"
echo "profile and energy model it chose (the escape rows include the difference between its walks"
echo "and the study's):"
echo
echo "| scene | tolerance | chosen (profile/method, energy) | error vs exact | time (s) |"
echo "|---|---|---|---|---|"
awk -F, '$4 == "bake-auto" { printf "| %s | %s | %s, %s | %.4f%s | %.3f |\n", $1, $6, $5, $20, $16, ($16 <= $6 ? "" : " **missed**"), $11 }' "$dir/scenes.csv"
} > "$dir/auto_check.md"
echo "charts and tables in $dir"
