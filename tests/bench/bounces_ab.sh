#!/usr/bin/env bash
# Two builds' default bake (--bounces auto) and --bounces 0 on dragon_res2 (150 mm marble,
# forest.exr, 2 threads), alternating in one run: what a change to the bounces costs or saves,
# and each build's default-over-bounces-0 ratio measured beside the other's (issue 36's 1.25x).
#   tests/bench/bounces_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]
# RUNS per side and setting (default 5). Writes tests/bench/results/bake/bounces_ab.csv (one
# line per run: the tool's JSON stage seconds) and bounces_ab_summary.csv (per build and setting
# the medians; per build the ratio).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
before=$(realpath "${1:?usage: bounces_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
after=$(realpath "${2:?usage: bounces_ab.sh BEFORE_BUILD AFTER_BUILD [RUNS]}")
runs=${3:-5}
out=$root/tests/bench/results/bake
data=$root/data/cache
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
csv=$out/bounces_ab.csv
echo "build,bounces_arg,run,total_s,irradiance_s,interreflection_s,exitance_s,bounces,gather_rays" \
  >"$csv.tmp"
for run in $(seq "$runs"); do
  for side in before after; do
    build=$before
    [[ $side == after ]] && build=$after
    for arg in auto 0; do
      "$build/tools/sss-bake" "$data/meshes/dragon_res2.ply" -e "$data/env/forest.exr" \
        -m marble --size-mm 150 --threads 2 --quiet --bounces "$arg" -o "$work/out.ply" \
        --json "$work/r.json"
      python3 - "$work/r.json" "$side" "$arg" "$run" >>"$csv.tmp" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s, ir = r["stages"], r["interreflection"]
print(f'{sys.argv[2]},{sys.argv[3]},{sys.argv[4]},{s["total_s"]:.3f},{s["irradiance_s"]:.3f},'
      f'{ir["seconds"]:.3f},{s["exitance_s"]:.3f},{ir.get("bounces", 0)},'
      f'{ir.get("gather_rays", 0)}')
PY
    done
  done
done
mv "$csv.tmp" "$csv"
python3 - "$csv" "$out/bounces_ab_summary.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def median(build, arg, key):
    return statistics.median(float(r[key]) for r in rows
                             if r["build"] == build and r["bounces_arg"] == arg)
with open(sys.argv[2], "w") as f:
    f.write("build,default_median_s,bounces0_median_s,default_over_bounces0,"
            "interreflection_median_s,irradiance_default_s,irradiance_bounces0_s\n")
    for b in ("before", "after"):
        d, z = median(b, "auto", "total_s"), median(b, "0", "total_s")
        f.write(f"{b},{d:.3f},{z:.3f},{d / z:.3f},{median(b, 'auto', 'interreflection_s'):.3f},"
                f"{median(b, 'auto', 'irradiance_s'):.3f},{median(b, '0', 'irradiance_s'):.3f}\n")
PY
cat "$out/bounces_ab_summary.csv"
