#!/usr/bin/env bash
# The compact lights' mirror images (lib/transport/mirrored_lights.h), two builds of sss-bake in one
# run: the gather's noise each bake reports (interreflection.gather_noise), the noise two seeds
# measure (the relative RMS of their difference in the radiance along the normal over sqrt 2, and
# the largest relative difference of one value), and the bake's time (median of RUNS alternated
# runs per side, default 3). The far field is off, so that the gather's noise is not hidden under
# its own. Writes tests/bench/results/bake/mirrored_lights_ab.csv (or OUT.csv).
#   bash tests/bench/mirrored_lights_ab.sh BEFORE_SSS_BAKE AFTER_SSS_BAKE [OUT.csv] [RUNS]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
before=$(realpath "$1") after=$(realpath "$2")
out=${3:-tests/bench/results/bake/mirrored_lights_ab.csv} runs=${4:-3}
bash data/fetch.sh >/dev/null
data=data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

median() { tr ' ' '\n' | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
json() { python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print($1)" "$2"; }

echo "scene,light,before_gather_noise,after_gather_noise,before_seed_noise,after_seed_noise,before_seed_worst,after_seed_worst,before_bake_s,after_bake_s,after_over_before" >"$work/out.csv"
for scene in bunny:50 dragon_res2:150; do
  mesh=${scene%%:*} size=${scene##*:}
  for light in sunrise courtyard sun; do
    if [ "$light" = sun ]; then env=(--sky elevation=30,azimuth=60); else env=(-e "$data/env/$light.exr"); fi
    declare -A seconds=([before]="" [after]="")
    for ((i = 0; i < runs; ++i)); do
      for side in before after; do
        bake=${!side} seed=$((i % 2 + 1))
        "$bake" "$data/meshes/$mesh.ply" "${env[@]}" -m marble --size-mm "$size" --far-field off \
          --seed "$seed" -q -o "$work/$side-$i.ply" --json "$work/$side-$i.json"
        seconds[$side]="${seconds[$side]} $(json "j['stages']['total_s']" "$work/$side-$i.json")"
      done
      echo "mirrored_lights_ab: $mesh $light run $((i + 1))/$runs" >&2
    done
    row="$mesh-marble-$size,$light"
    for side in before after; do
      row="$row,$(json "round(j['interreflection']['gather_noise'], 5)" "$work/$side-0.json")"
    done
    for side in before after; do
      read -r rms worst < <(python3 tests/bench/ply_radiance_change.py "$work/$side-0.ply" "$work/$side-1.ply")
      eval "${side}_rms=$rms ${side}_worst=$worst"
    done
    row="$row,$(awk -v a="$before_rms" 'BEGIN { printf "%.5f", a / sqrt(2) }'),$(awk -v a="$after_rms" 'BEGIN { printf "%.5f", a / sqrt(2) }')"
    row="$row,$before_worst,$after_worst"
    bm=$(echo ${seconds[before]} | median) am=$(echo ${seconds[after]} | median)
    row="$row,$(printf '%.3f,%.3f,%.3f' "$bm" "$am" "$(awk -v a="$am" -v b="$bm" 'BEGIN { print a / b }')")"
    echo "$row" >>"$work/out.csv"
  done
done
mv "$work/out.csv" "$out"
cat "$out"
