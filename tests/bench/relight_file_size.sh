#!/usr/bin/env bash
# What an order-6 relightable bake's file weighs, and what storing its bands from 4 in 8 bits
# (mesh/quantized_transfer.h) does to the light relit from it. dragon_res2 (150 mm marble) and the
# bunny (50 mm marble) under forest.exr, 2 threads: the plain bake's PLY and GLB against the order-6
# ones. With a baseline build that stores every band in 16 bits (format 2), its order-6 PLY of
# the same bake is relit beside this build's, both by this build, under four HDRs turned 30
# degrees: the relative RMS of the radiance along the normal between the two. Without one, those
# two columns are kept from the CSV's row of the same scene (the PLY's storage of the bands is
# what they measure; a change to the GLB's layout alone does not move them).
#   tests/bench/relight_file_size.sh BUILD_DIR [BASELINE_BUILD_DIR]
# Writes tests/bench/results/relight/file_size.csv.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: relight_file_size.sh BUILD_DIR [BASELINE_BUILD_DIR]}")
baseline=${2:+$(realpath "$2")}
out=$root/tests/bench/results/relight
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"
csv=$out/file_size.csv
echo "scene,plain_bytes,order6_bytes,order6_glb_bytes,order6_ratio,order6_glb_ratio,relit_change_rms,relit_change_max" >"$csv.tmp"
# The relative RMS and largest relative difference of radiance_normal_r/g/b between two baked PLYs.
compare() { python3 "$root/tests/bench/ply_radiance_change.py" "$@"; }
for scene in "dragon_res2 marble 150" "bunny marble 50"; do
  read -r mesh material size <<<"$scene"
  bake=(-e "$data/env/forest.exr" -m "$material" --size-mm "$size" --threads 2 --quiet)
  "$build/tools/sss-bake" "$data/meshes/$mesh.ply" "${bake[@]}" -o "$work/plain.ply"
  "$build/tools/sss-bake" "$data/meshes/$mesh.ply" "${bake[@]}" -o "$work/plain.glb"
  "$build/tools/sss-bake" "$data/meshes/$mesh.ply" "${bake[@]}" --relightable 6 -o "$work/r6.ply"
  "$build/tools/sss-bake" "$data/meshes/$mesh.ply" "${bake[@]}" --relightable 6 -o "$work/r6.glb"
  read -r rms worst < <(awk -F, -v s="$mesh-$material-$size" '$1 == s {print $7, $8}' \
    "$csv" 2>/dev/null) || true
  if [[ -n $baseline ]]; then
    "$baseline/tools/sss-bake" "$data/meshes/$mesh.ply" "${bake[@]}" --relightable 6 \
      -o "$work/r6_16bit.ply"
    rms=0 worst=0
    for env in sunset city studio courtyard; do
      for file in r6 r6_16bit; do
        "$build/tools/sss-relight" "$work/$file.ply" -e "$data/env/$env.exr" --env-rotate 30 \
          --threads 2 --quiet -o "$work/relit_$file.ply"
      done
      read -r r w < <(compare "$work/relit_r6.ply" "$work/relit_r6_16bit.ply")
      rms=$(python3 -c "print(max($rms, $r))") worst=$(python3 -c "print(max($worst, $w))")
    done
  fi
  python3 - "$mesh-$material-$size" "$work" "$rms" "$worst" >>"$csv.tmp" <<'PY'
import os, sys
scene, w, rms, worst = sys.argv[1:]
plain, plain_glb, ply, glb = (os.path.getsize(f"{w}/{f}")
                              for f in ("plain.ply", "plain.glb", "r6.ply", "r6.glb"))
print(f"{scene},{plain},{ply},{glb},{ply / plain:.3f},{glb / plain_glb:.3f},{rms},{worst}")
PY
done
mv "$csv.tmp" "$csv"
cat "$csv"
