#!/usr/bin/env bash
# What each environment costs once the relightable bake is read and its session built: one
# sss-relight process relights the bake under several environments (the batch a pipeline runs,
# and what sss-render's light turntable does per frame), and each environment's report gives its
# own relight and write. dragon_res2 (150 mm marble) and the bunny (50 mm marble), baked once per
# run under forest.exr with --relightable (order 3); relit under a smooth sky without a compact
# light (a vertical gradient, written here) and sunset, forest, city, courtyard and studio, in that
# order after a first sunset that pays for the read and the session. 2 threads.
#   tests/bench/relight_batch.sh BUILD_DIR [RUNS]
# Writes tests/bench/results/relight/batch.csv (one line per run, scene and environment) and
# batch_summary.csv: per scene the medians of the first environment (the read, the session and
# its relight), of the smooth sky's relight, and of the HDRs' (each with its compact lights).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: relight_batch.sh BUILD_DIR [RUNS]}")
runs=${2:-3}
out=$root/tests/bench/results/relight
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out" "$work/env"
python3 "$root/tests/bench/smooth_sky.py" "$work/env/smooth.hdr"
cp "$data/env/sunset.exr" "$work/env/first_sunset.exr"
for e in sunset forest city courtyard studio; do ln -s "$data/env/$e.exr" "$work/env/$e.exr"; done
envs=(first_sunset.exr smooth.hdr sunset.exr forest.exr city.exr courtyard.exr studio.exr)
csv=$out/batch.csv
echo "scene,run,environment,position,compact_lights,seconds,compact_lights_s,smooth_s,compact_transport_s,gather_s,bounces_s" >"$csv.tmp"
for run in $(seq "$runs"); do
  for scene in "dragon_res2 marble 150" "bunny marble 50"; do
    read -r mesh material size <<<"$scene"
    "$build/tools/sss-bake" "$data/meshes/$mesh.ply" -e "$data/env/forest.exr" -m "$material" \
      --size-mm "$size" --threads 2 --quiet --relightable -o "$work/relightable.ply"
    args=()
    for e in "${envs[@]}"; do args+=(-e "$work/env/$e"); done
    rm -rf "$work/relit"
    "$build/tools/sss-relight" "$work/relightable.ply" "${args[@]}" --threads 2 --quiet \
      -o "$work/relit/" --json "$work/relit/"
    python3 - "$work/relit" "$mesh-$material-$size" "$run" "${envs[@]}" >>"$csv.tmp" <<'PY'
import json, os, sys
folder, scene, run, envs = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
for position, env in enumerate(envs):
    name = os.path.splitext(env)[0]
    r = json.load(open(os.path.join(folder, f"relightable_{name}.json")))
    s = r["stages"]
    print(f'{scene},{run},{name},{position},{r["compact_lights"]},{r["seconds"]:.4f},' +
          ",".join(f'{s[k]:.4f}' for k in ("compact_lights_s", "smooth_s", "compact_transport_s",
                                           "gather_s", "bounces_s")))
PY
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/batch_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("scene,first_s,smooth_sky_s,hdr_median_s,hdr_max_s,hdr_compact_transport_s,"
            "hdr_bounces_s,runs\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        s = [r for r in rows if r["scene"] == scene]
        med = lambda rs, k: statistics.median(float(r[k]) for r in rs)
        first = [r for r in s if r["position"] == "0"]
        smooth = [r for r in s if r["environment"] == "smooth"]
        hdrs = [r for r in s if int(r["position"]) >= 2]
        # Per HDR the median over the runs, then the median and the largest of the five.
        per_hdr = [med([r for r in hdrs if r["environment"] == e], "seconds")
                   for e in dict.fromkeys(r["environment"] for r in hdrs)]
        f.write(f'{scene},{med(first, "seconds"):.4f},{med(smooth, "seconds"):.4f},'
                f'{statistics.median(per_hdr):.4f},{max(per_hdr):.4f},'
                f'{med(hdrs, "compact_transport_s"):.4f},{med(hdrs, "bounces_s"):.4f},'
                f'{len(first)}\n')
PY
cat "$out/batch_summary.csv"
