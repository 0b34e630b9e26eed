#!/usr/bin/env bash
# What the gather's rays following the tolerance (bake_settings.h, gatherRaysFor) change: sss-bake
# of two builds (BEFORE: 64 rays at any tolerance), alternated, on dragon_res2 (150 mm marble,
# forest.exr, 2 threads) at --tolerance 0.01, 0.02 and 0.03: the total and the interreflection
# stage's seconds, the bounces, the gather's noise and the predicted error; and whether the 1 %
# outputs are byte-identical.
#   tests/bench/gather_rays_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]
# Writes tests/bench/results/bake/gather_rays.csv (one line per run) and gather_rays_summary.csv.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
before=$(realpath "${1:?usage: gather_rays_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
after=$(realpath "${2:?usage: gather_rays_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
runs=${3:-3}
out=$root/tests/bench/results/bake
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
csv=$out/gather_rays.csv
echo "tolerance,build,run,total_s,interreflection_s,bounces,gather_noise,estimated_error,identical" >"$csv.tmp"
for run in $(seq "$runs"); do
  for tolerance in 0.01 0.02 0.03; do
    for build in before after; do
      dir=$before
      [[ $build == after ]] && dir=$after
      "$dir/tools/sss-bake" "$data/meshes/dragon_res2.ply" -e "$data/env/forest.exr" -m marble \
        --size-mm 150 --tolerance "$tolerance" --threads 2 --quiet -o "$work/$build.ply" \
        --json "$work/$build.json"
      identical=""
      [[ $build == after ]] && { cmp -s "$work/before.ply" "$work/after.ply" && identical=yes || identical=no; }
      python3 - "$work/$build.json" "$tolerance" "$build" "$run" "$identical" >>"$csv.tmp" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
ir = r["interreflection"]
print(f'{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{r["stages"]["total_s"]:.3f},'
      f'{ir.get("seconds", 0.0):.3f},{ir["bounces"]},{ir.get("gather_noise", 0.0):.5f},'
      f'{r["estimated_error"]["total"]:.5f},{sys.argv[5]}')
PY
    done
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/gather_rays_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
with open(sys.argv[2], "w") as f:
    f.write("tolerance,before_s,after_s,after_over_before,before_interreflection_s,"
            "after_interreflection_s,before_gather_noise,after_gather_noise,before_error,"
            "after_error,identical\n")
    for tol in dict.fromkeys(r["tolerance"] for r in rows):
        b = [r for r in rows if r["tolerance"] == tol and r["build"] == "before"]
        a = [r for r in rows if r["tolerance"] == tol and r["build"] == "after"]
        med = lambda s, k: statistics.median(float(r[k]) for r in s)
        f.write(f'{tol},{med(b, "total_s"):.3f},{med(a, "total_s"):.3f},'
                f'{med(a, "total_s") / med(b, "total_s"):.3f},{med(b, "interreflection_s"):.3f},'
                f'{med(a, "interreflection_s"):.3f},{b[0]["gather_noise"]},{a[0]["gather_noise"]},'
                f'{b[0]["estimated_error"]},{a[0]["estimated_error"]},'
                f'{"yes" if all(r["identical"] == "yes" for r in a) else "no"}\n')
PY
cat "$out/gather_rays_summary.csv"
