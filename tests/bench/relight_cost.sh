#!/usr/bin/env bash
# What relighting costs, with the tools as a user runs them: sss-bake with its defaults against
# the same with --relightable (order 3), alternating, and sss-relight of the relightable bake under
# sunset.exr, on dragon_res2 (150 mm marble) and the bunny (50 mm marble), under forest.exr,
# 2 threads; the files' sizes.
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
echo "scene,run,plain_bake_s,relightable_bake_s,relight_stage_s,relight_s,plain_bytes,relightable_bytes" >"$csv.tmp"
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
    python3 - "$work" "$mesh-$material-$size" "$run" >>"$csv.tmp" <<'PY'
import json, os, sys
w = sys.argv[1]
plain = json.load(open(f"{w}/plain.json"))
relightable = json.load(open(f"{w}/relightable.json"))
relit = json.load(open(f"{w}/relit.json"))
print(f'{sys.argv[2]},{sys.argv[3]},{plain["stages"]["total_s"]:.3f},'
      f'{relightable["stages"]["total_s"]:.3f},{relightable["relightable"]["seconds"]:.3f},'
      f'{relit["seconds"]:.3f},{os.path.getsize(f"{w}/plain.ply")},'
      f'{os.path.getsize(f"{w}/relightable.ply")}')
PY
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/cost_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("scene,plain_bake_s,relightable_bake_s,relightable_over_plain,relight_s,"
            "relight_over_plain_bake,plain_bytes,relightable_bytes,bytes_ratio\n")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        s = [r for r in rows if r["scene"] == scene]
        med = lambda k: statistics.median(float(r[k]) for r in s)
        p, r, l = med("plain_bake_s"), med("relightable_bake_s"), med("relight_s")
        pb, rb = int(s[0]["plain_bytes"]), int(s[0]["relightable_bytes"])
        f.write(f"{scene},{p:.3f},{r:.3f},{r / p:.3f},{l:.3f},{l / p:.3f},{pb},{rb},"
                f"{rb / pb:.3f}\n")
PY
cat "$out/cost_summary.csv"
