#!/usr/bin/env bash
# What relighting costs sss-render per frame, on this machine's GL (llvmpipe here):
#   draw: one frame drawn (--frames, median wall ms with glFinish) of a relightable bake relit on
#     the GPU (its smooth light summed in the vertex shader) against the same bake drawn as baked
#     (--no-relight), 1024 x 1024, 4 samples;
#   turntable: a light turntable's cost per frame, the environment turned and the bake relit
#     (--relight-on gpu or cpu) or drawn as baked (--no-relight: the background and the
#     reflections turn), from the process's wall time at 9 frames less that at 1, over 8;
#     512 x 512.
# dragon_res2 (150 mm marble) and the bunny (50 mm marble), baked once per run under forest.exr
# with --relightable (order 3, the default bounces); lit by sunset.exr (one compact light) and by a
# smooth sky without a compact light (written here). The modes alternate within a run. 2 threads.
#   tests/bench/relight_frame.sh BUILD_DIR [RUNS]
# Writes tests/bench/results/relight/frame.csv (one line per run, scene, environment and mode)
# and frame_summary.csv (medians, and each mode over --no-relight).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: relight_frame.sh BUILD_DIR [RUNS]}")
runs=${2:-3}
out=$root/tests/bench/results/relight
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
python3 "$root/tests/bench/smooth_sky.py" "$work/smooth.hdr"
render=("$build/tools/sss-render" --threads 2 --quiet)
# shellcheck source=tests/bench/elapsed.sh
source "$root/tests/bench/elapsed.sh"
csv=$out/frame.csv
echo "scene,run,environment,mode,draw_ms,turntable_frame_s" >"$csv.tmp"
for run in $(seq "$runs"); do
  for scene in "dragon_res2 marble 150" "bunny marble 50"; do
    read -r mesh material size <<<"$scene"
    "$build/tools/sss-bake" "$data/meshes/$mesh.ply" -e "$data/env/forest.exr" -m "$material" \
      --size-mm "$size" --threads 2 --quiet --relightable -o "$work/relightable.ply"
    for env in "$data/env/sunset.exr" "$work/smooth.hdr"; do
      name=$(basename "${env%.*}")
      for mode in "--no-relight" "--relight-on gpu" "--relight-on cpu"; do
        # shellcheck disable=SC2086 # the mode is one or two words
        "${render[@]}" "$work/relightable.ply" -e "$env" $mode --frames 20 --size 1024x1024 \
          -o "$work/draw.png" --json "$work/draw.json" >/dev/null
        draw=$(python3 -c "import json; print(json.load(open('$work/draw.json'))['frames']['median_ms'])")
        turn=()
        for n in 1 9; do
          # shellcheck disable=SC2086
          turn+=("$(elapsed "${render[@]}" "$work/relightable.ply" -e "$env" $mode \
            --light-turntable $n --size 512x512 -o "$work/turn.png")")
        done
        per_frame=$(python3 -c "print(f'{(${turn[1]} - ${turn[0]}) / 8:.4f}')")
        echo "$mesh-$material-$size,$run,$name,${mode#--},$draw,$per_frame" >>"$csv.tmp"
      done
    done
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/frame_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
med = lambda rs, k: statistics.median(float(r[k]) for r in rs)
with open(sys.argv[2], "w") as f:
    f.write("scene,environment,mode,draw_ms,draw_ratio,turntable_frame_s,turntable_ratio,runs\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        for env in dict.fromkeys(r["environment"] for r in rows):
            base = [r for r in rows if r["scene"] == scene and r["environment"] == env and
                    r["mode"] == "no-relight"]
            for mode in dict.fromkeys(r["mode"] for r in rows):
                s = [r for r in rows if r["scene"] == scene and r["environment"] == env and
                     r["mode"] == mode]
                f.write(f'{scene},{env},{mode},{med(s, "draw_ms"):.2f},'
                        f'{med(s, "draw_ms") / med(base, "draw_ms"):.3f},'
                        f'{med(s, "turntable_frame_s"):.4f},'
                        f'{med(s, "turntable_frame_s") / med(base, "turntable_frame_s"):.2f},'
                        f'{len(s)}\n')
PY
cat "$out/frame_summary.csv"
