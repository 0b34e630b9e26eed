#!/usr/bin/env bash
# What the default --bounces auto costs: sss-bake with its defaults against the same binary with
# --bounces 0, alternating, on dragon_res2 (150 mm marble), the bunny (50 mm marble and skim
# milk) and a convex sphere-like mesh (dragon_res4 at 150 mm is concave too; the teapot at 100 mm
# marble), under forest.exr, 2 threads.
#   tests/bench/default_bounces_ab.sh BUILD_DIR [RUNS]
# Writes tests/bench/results/bake/default_bounces.csv: one line per run (the tool's JSON: total
# and interreflection seconds, bounces done, the estimated error with and without bounces), and
# default_bounces_summary.csv: per scene the medians and their ratio.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: default_bounces_ab.sh BUILD_DIR [RUNS]}")
runs=${2:-3}
out=$root/tests/bench/results/bake
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scenes=("dragon_res2 marble 150" "bunny marble 50" "bunny skimmilk 50" "teapot marble 100")
csv=$out/default_bounces.csv
echo "scene,bounces_arg,run,total_s,interreflection_s,bounces,estimated_error,estimated_missing" >"$csv.tmp"
for run in $(seq "$runs"); do
  for scene in "${scenes[@]}"; do
    read -r mesh material size <<<"$scene"
    for arg in default 0; do
      extra=()
      [[ $arg == 0 ]] && extra=(--bounces 0)
      "$build/tools/sss-bake" "$data/meshes/$mesh.ply" -e "$data/env/forest.exr" -m "$material" \
        --size-mm "$size" --threads 2 --quiet "${extra[@]}" -o "$work/out.ply" --json "$work/r.json"
      python3 - "$work/r.json" "$mesh-$material-$size" "$arg" "$run" >>"$csv.tmp" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ir = r["interreflection"]
print(f'{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{r["stages"]["total_s"]:.3f},'
      f'{ir["seconds"]:.3f},{ir["bounces"]},{r["estimated_error"]["total"]:.4f},'
      f'{ir.get("estimated_missing", 0.0):.4f}')
PY
    done
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/default_bounces_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("scene,default_median_s,bounces0_median_s,default_over_bounces0,bounces,"
            "estimated_error_default,estimated_error_bounces0\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        d = [r for r in rows if r["scene"] == scene and r["bounces_arg"] == "default"]
        z = [r for r in rows if r["scene"] == scene and r["bounces_arg"] == "0"]
        md = statistics.median(float(r["total_s"]) for r in d)
        mz = statistics.median(float(r["total_s"]) for r in z)
        f.write(f"{scene},{md:.3f},{mz:.3f},{md / mz:.3f},{d[0]['bounces']},"
                f"{d[0]['estimated_error']},{z[0]['estimated_error']}\n")
PY
cat "$out/default_bounces_summary.csv"
