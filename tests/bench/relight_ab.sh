#!/usr/bin/env bash
# Two builds' relightable bake and sss-relight measured in one run, alternating, each relighting
# its own build's bake (so that a change to what the bake stores counts): dragon_res2 (150 mm
# marble) and the bunny (50 mm marble), baked under forest.exr with the defaults and
# --relightable, relit under sunset.exr, 2 threads. How far the two builds' relit light differs
# is measured too: the relative RMS over the vertices of the radiance along the normal (0 where
# the change is speed alone).
#   tests/bench/relight_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]
# RUNS per side (default 5). Writes tests/bench/results/relight/relight_ab.csv: per scene and
# build the median relightable bake, relight and gather seconds, the after / before ratios, and
# the largest relit change over the runs.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
before=$(realpath "${1:?usage: relight_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
after=$(realpath "${2:?usage: relight_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
runs=${3:-5}
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scenes=("dragon_res2 marble 150" "bunny marble 50")
echo "scene,side,run,bake_s,relight_s,gather_s,relit_change" >"$work/runs.csv"
for run in $(seq "$runs"); do
  for scene in "${scenes[@]}"; do
    read -r mesh material size <<<"$scene"
    for side in before after; do
      build=$before
      [[ $side == after ]] && build=$after
      "$build/tools/sss-bake" "$data/meshes/$mesh.ply" -e "$data/env/forest.exr" -m "$material" \
        --size-mm "$size" --threads 2 --quiet --relightable -o "$work/$mesh-$side.ply" \
        --json "$work/bake.json"
      "$build/tools/sss-relight" "$work/$mesh-$side.ply" -e "$data/env/sunset.exr" --threads 2 \
        --quiet -o "$work/$mesh-$side-relit.ply" --json "$work/relit.json"
      python3 -c 'import json, sys; b = json.load(open(sys.argv[1])); r = json.load(open(sys.argv[2]))
print("%s,%s,%s,%.3f,%.3f,%.3f" % (*sys.argv[3:6], b["stages"]["total_s"], r["seconds"],
                                   r["stages"]["gather_s"]))' \
        "$work/bake.json" "$work/relit.json" "$mesh-$material-$size" "$side" "$run" >"$work/$side.row"
    done
    read -r change _ < <(python3 "$root/tests/bench/ply_radiance_change.py" \
      "$work/$mesh-after-relit.ply" "$work/$mesh-before-relit.ply")
    for side in before after; do echo "$(cat "$work/$side.row"),$change" >>"$work/runs.csv"; done
  done
done
python3 - "$work/runs.csv" "$root/tests/bench/results/relight/relight_ab.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("scene,before_bake_s,after_bake_s,bake_ratio,before_relight_s,after_relight_s,"
            "relight_ratio,before_gather_s,after_gather_s,gather_ratio,relit_change_rms,runs\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        med = lambda side, k: statistics.median(
            float(r[k]) for r in rows if r["scene"] == scene and r["side"] == side)
        bb, ba = med("before", "bake_s"), med("after", "bake_s")
        b, a = med("before", "relight_s"), med("after", "relight_s")
        gb, ga = med("before", "gather_s"), med("after", "gather_s")
        n = sum(1 for r in rows if r["scene"] == scene and r["side"] == "after")
        change = max(float(r["relit_change"]) for r in rows if r["scene"] == scene)
        f.write(f"{scene},{bb:.3f},{ba:.3f},{ba / bb:.3f},{b:.3f},{a:.3f},{a / b:.3f},{gb:.3f},"
                f"{ga:.3f},{ga / gb:.3f},{change:.2e},{n}\n")
PY
cat "$root/tests/bench/results/relight/relight_ab.csv"
