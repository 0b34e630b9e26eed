#!/usr/bin/env bash
# Draws the relighting error chart from relight_study's CSVs (tests/bench/results/relight/
# traced_off/relight.csv and defaults/relight.csv): per light (the 8 HDRs at 8 turns, the sun
# from 8 directions) the relative RMS of the radiance along the normal against a fresh bake, per
# scene at SH orders 3 and 6, with the issue's targets (2 % for the HDRs, 3 % for the sun).
#   tests/bench/relight_charts.sh [DIR]     writes DIR/relight_error.png
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
dir=${1:-$root/tests/bench/results/relight}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# One table per study: case index, label, then relative RMS (%) per scene and order.
for study in traced_off defaults; do
  python3 - "$dir/$study/relight.csv" "$work/$study" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["kind"] in ("hdr", "sun")]
scenes = list(dict.fromkeys(r["scene"] for r in rows))
cases = list(dict.fromkeys((r["kind"], r["light"], r["rotate_deg"]) for r in rows))
cases.sort(key=lambda c: (c[0] == "sun", c[1], float(c[2])))
value = {(r["scene"], r["kind"], r["light"], r["rotate_deg"], r["sh_order"]): float(r["relative_rms"])
         for r in rows}
with open(sys.argv[2] + ".dat", "w") as out:
    for i, (kind, light, turn) in enumerate(cases):
        label = light if kind == "sun" else (light if turn == "0" else "")
        cells = [f"{100 * value.get((s, kind, light, turn, o), float('nan')):.4g}"
                 for s in scenes for o in ("3", "6")]
        out.write(f'{i} "{label}" ' + " ".join(cells) + "\n")
open(sys.argv[2] + ".scenes", "w").write(" ".join(scenes))
open(sys.argv[2] + ".hdrs", "w").write(str(sum(1 for c in cases if c[0] == "hdr")))
PY
done
plot_panel() {  # study, title
  local scenes hdrs
  scenes=$(cat "$work/$1.scenes")
  hdrs=$(cat "$work/$1.hdrs")
  cat <<GP
set title "$2"
set arrow 1 from -0.5,2 to $hdrs-0.5,2 nohead dt 2 lw 2 lc rgb "black" front
set arrow 2 from $hdrs-0.5,3 to $hdrs+7.5,3 nohead dt 2 lw 2 lc rgb "black" front
set arrow 3 from $hdrs-0.5,graph 0 to $hdrs-0.5,graph 1 nohead lc rgb "gray"
set xrange [-0.5:$hdrs+7.5]
n = words("$scenes")
plot for [s = 1:n] "$work/$1.dat" using 1:(column(1 + 2 * s)):xtic(2) with points pt 6 ps 1.1 \
       lc s title word("$scenes", s)." order 3", \
     for [s = 1:n] "$work/$1.dat" using 1:(column(2 + 2 * s)) with points pt 7 ps 1.1 \
       lc s title word("$scenes", s)." order 6"
GP
}
gnuplot <<GP
set terminal pngcairo size 1400,1000 font ",10" noenhanced
set output "$dir/relight_error.png"
set multiplot layout 2,1
set logscale y
set yrange [0.05:50]
set ylabel "relative RMS of radiance along the normal, %"
set xtics rotate by 60 right
set grid y
set key outside right top
$(plot_panel traced_off "Relit against fresh bakes: the stored transfer alone (far field and unscattered light off); dashed: the issue's targets")
$(plot_panel defaults "Relit against fresh bakes with sss-bake's defaults (far field and unscattered light traced in the fresh bakes)")
unset multiplot
GP
echo "$dir/relight_error.png"
