#!/usr/bin/env bash
# Two builds' relightable bake and sss-relight measured in one run, alternating, each relighting
# its own build's bake (so that a change to what the bake stores counts): dragon_res2 (150 mm
# marble) and the bunny (50 mm marble), baked under forest.exr with the defaults and
# --relightable, relit under sunset.exr, 2 threads. The relit files must hold the same vertex data
# (a speed change that moves the light is not measured here).
#   tests/bench/relight_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]
# RUNS per side (default 5). Writes tests/bench/results/relight/relight_ab.csv: per scene and
# build the median relightable bake, relight and gather seconds, and the after / before ratios.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
before=$(realpath "${1:?usage: relight_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
after=$(realpath "${2:?usage: relight_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
runs=${3:-5}
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scenes=("dragon_res2 marble 150" "bunny marble 50")
# The vertex data of a baked PLY: the bytes after its header (the header names the input path).
body() { python3 -c 'import sys; b = open(sys.argv[1], "rb").read(); sys.stdout.buffer.write(b[b.index(b"end_header\n"):])' "$1"; }
echo "scene,side,run,bake_s,relight_s,gather_s" >"$work/runs.csv"
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
        "$work/bake.json" "$work/relit.json" "$mesh-$material-$size" "$side" "$run" >>"$work/runs.csv"
    done
    cmp <(body "$work/$mesh-before-relit.ply") <(body "$work/$mesh-after-relit.ply") >/dev/null ||
      echo "relight_ab: $mesh: the two builds relight to different vertex data" >&2
  done
done
python3 - "$work/runs.csv" "$root/tests/bench/results/relight/relight_ab.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("scene,before_bake_s,after_bake_s,bake_ratio,before_relight_s,after_relight_s,"
            "relight_ratio,before_gather_s,after_gather_s,gather_ratio,runs\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        med = lambda side, k: statistics.median(
            float(r[k]) for r in rows if r["scene"] == scene and r["side"] == side)
        bb, ba = med("before", "bake_s"), med("after", "bake_s")
        b, a = med("before", "relight_s"), med("after", "relight_s")
        gb, ga = med("before", "gather_s"), med("after", "gather_s")
        n = sum(1 for r in rows if r["scene"] == scene and r["side"] == "after")
        f.write(f"{scene},{bb:.3f},{ba:.3f},{ba / bb:.3f},{b:.3f},{a:.3f},{a / b:.3f},{gb:.3f},"
                f"{ga:.3f},{ga / gb:.3f},{n}\n")
PY
cat "$root/tests/bench/results/relight/relight_ab.csv"
