#!/usr/bin/env bash
# Does the noise a bake reports hold? Each scene under each sample HDR is baked with sss-bake's
# defaults and two seeds; the two bakes' relative RMS difference of the radiance along the normal
# (over vertices and channels) over sqrt 2 is one bake's noise, measured, against the numerical
# error both reports give (estimated_error.numerical, their mean: the noise and truncation the
# tolerance controls). The scenes: dragon_res2 (150 mm marble), the bunny (50 mm marble and skim
# milk), dragon_res3 (100 mm skim milk), 2 threads.
#   tests/bench/seed_spread.sh BUILD_DIR
# Writes tests/bench/results/accuracy/seed_spread.csv: per scene and HDR the measured and the
# reported noise, their ratio (<= 1: the report holds), the worst vertex's relative difference, and
# whether the unscattered light was traced in either bake.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: seed_spread.sh BUILD_DIR}")
out=$root/tests/bench/results/accuracy
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scenes=("dragon_res2 marble 150" "bunny marble 50" "bunny skimmilk 50" "dragon_res3 skimmilk 100")
envs=(city courtyard forest interior night studio sunrise sunset)
csv=$out/seed_spread.csv
echo "scene,environment,measured_noise,reported_numerical,measured_over_reported,worst_vertex,unscattered_traced" >"$csv.tmp"
for scene in "${scenes[@]}"; do
  read -r mesh material size <<<"$scene"
  for env in "${envs[@]}"; do
    for seed in 1 2; do
      "$build/tools/sss-bake" "$data/meshes/$mesh.ply" -e "$data/env/$env.exr" -m "$material" \
        --size-mm "$size" --threads 2 --quiet --seed "$seed" -o "$work/s$seed.ply" \
        --json "$work/s$seed.json"
    done
    read -r rms worst < <(python3 "$root/tests/bench/ply_radiance_change.py" "$work/s1.ply" "$work/s2.ply")
    python3 - "$work" "$mesh-$material-$size" "$env" "$rms" "$worst" >>"$csv.tmp" <<'PY'
import json, math, sys
work, scene, env, rms, worst = sys.argv[1:]
reports = [json.load(open(f"{work}/s{k}.json")) for k in (1, 2)]
reported = sum(r["estimated_error"]["numerical"] for r in reports) / 2
measured = float(rms) / math.sqrt(2)
traced = int(any(r["unscattered"]["traced"] for r in reports))
print(f"{scene},{env},{measured:.4f},{reported:.4f},{measured / reported:.2f},{float(worst):.3f},{traced}")
PY
  done
done
mv "$csv.tmp" "$csv"
cat "$csv"
