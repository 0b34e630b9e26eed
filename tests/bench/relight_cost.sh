#!/usr/bin/env bash
# What relighting costs, with the tools as a user runs them: sss-bake with its defaults against
# the same with --relightable (order 3), alternating, and sss-relight of the relightable bake under
# sunset.exr, on dragon_res2 (150 mm marble) and the bunny (50 mm marble), under forest.exr,
# 2 threads; sss-render's light turntable of it under sunset.exr, 1 frame against 5 (64x48, the
# relighting is most of a frame): what each further frame adds; the files' sizes at order 3 (first
# run only), PLY and GLB; where the relight's time went (sss-relight's report: its stages).
# Order 6's sizes: relight_file_size.sh.
#   tests/bench/relight_cost.sh BUILD_DIR [RUNS]
# Writes tests/bench/results/relight/cost.csv (one line per run) and cost_summary.csv (per scene
# the medians, their ratios, and the bytes).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: relight_cost.sh BUILD_DIR [RUNS]}")
runs=${2:-3}
out=$root/tests/bench/results/relight
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
scenes=("dragon_res2 marble 150" "bunny marble 50")
csv=$out/cost.csv
echo "scene,run,plain_bake_s,relightable_bake_s,relight_stage_s,relight_s,turntable1_s,turntable5_s,plain_bytes,relightable_bytes,plain_glb_bytes,relightable_glb_bytes,relight_compact_lights_s,relight_smooth_s,relight_compact_transport_s,relight_gather_s,relight_bounces_s" >"$csv.tmp"
# shellcheck source=tests/bench/elapsed.sh
source "$root/tests/bench/elapsed.sh"
seconds() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$@"; }
for run in $(seq "$runs"); do
  for scene in "${scenes[@]}"; do
    read -r mesh material size <<<"$scene"
    bake=("$build/tools/sss-bake" "$data/meshes/$mesh.ply" -e "$data/env/forest.exr" -m "$material"
      --size-mm "$size" --threads 2 --quiet)
    "${bake[@]}" -o "$work/plain.ply" --json "$work/plain.json"
    "${bake[@]}" --relightable -o "$work/relightable.ply" --json "$work/relightable.json"
    "$build/tools/sss-relight" "$work/relightable.ply" -e "$data/env/sunset.exr" --threads 2 \
      --quiet -o "$work/relit.ply" --json "$work/relit.json"
    turntable=("$build/tools/sss-render" "$work/relightable.ply" -e "$data/env/sunset.exr"
      --threads 2 --size 64x48 --quiet -o "$work/turntable.png" --light-turntable)
    t1=$(elapsed "${turntable[@]}" 1)
    t5=$(elapsed "${turntable[@]}" 5)
    if [[ $run == 1 ]]; then
      "${bake[@]}" -o "$work/$mesh-plain.glb"
      "${bake[@]}" --relightable -o "$work/$mesh-relightable.glb"
    fi
    python3 - "$work" "$mesh-$material-$size" "$run" "$t1" "$t5" "$mesh" >>"$csv.tmp" <<'PY'
import json, os, sys
w = sys.argv[1]
plain = json.load(open(f"{w}/plain.json"))
relightable = json.load(open(f"{w}/relightable.json"))
relit = json.load(open(f"{w}/relit.json"))
m = sys.argv[6]
print(f'{sys.argv[2]},{sys.argv[3]},{plain["stages"]["total_s"]:.3f},'
      f'{relightable["stages"]["total_s"]:.3f},{relightable["relightable"]["seconds"]:.3f},'
      f'{relit["seconds"]:.3f},{sys.argv[4]},{sys.argv[5]},{os.path.getsize(f"{w}/plain.ply")},'
      f'{os.path.getsize(f"{w}/relightable.ply")},{os.path.getsize(f"{w}/{m}-plain.glb")},'
      f'{os.path.getsize(f"{w}/{m}-relightable.glb")},' +
      ",".join(f'{relit["stages"][k]:.3f}' for k in
               ("compact_lights_s", "smooth_s", "compact_transport_s", "gather_s", "bounces_s")))
PY
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/cost_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("scene,plain_bake_s,relightable_bake_s,relightable_over_plain,relight_s,"
            "relight_over_plain_bake,turntable_frame_s,turntable_frame_over_relight,plain_bytes,"
            "relightable_bytes,bytes_ratio,glb_bytes_ratio,relight_compact_lights_s,"
            "relight_smooth_s,relight_compact_transport_s,relight_gather_s,relight_bounces_s\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        s = [r for r in rows if r["scene"] == scene]
        med = lambda k: statistics.median(float(r[k]) for r in s)
        p, r, l = med("plain_bake_s"), med("relightable_bake_s"), med("relight_s")
        frame = statistics.median((float(r["turntable5_s"]) - float(r["turntable1_s"])) / 4 for r in s)
        b = lambda k: int(s[0][k])
        f.write(f"{scene},{p:.3f},{r:.3f},{r / p:.3f},{l:.3f},{l / p:.3f},{frame:.3f},"
                f"{frame / l:.3f},{b('plain_bytes')},{b('relightable_bytes')},"
                f"{b('relightable_bytes') / b('plain_bytes'):.3f},"
                f"{b('relightable_glb_bytes') / b('plain_glb_bytes'):.3f},"
                + ",".join(f"{med('relight_' + k + '_s'):.3f}" for k in
                           ("compact_lights", "smooth", "compact_transport", "gather", "bounces"))
                + "\n")
PY
cat "$out/cost_summary.csv"
