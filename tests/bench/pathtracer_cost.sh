#!/usr/bin/env bash
# The bake against a volumetric path tracer at equal error (pathtracer_cost.cpp): the forward
# light tracer's time to the bake's measured error and to 3 %, over the bake's time, on the
# concavity study's bunny scenes, 2 threads, medians of RUNS alternated runs.
#   tests/bench/pathtracer_cost.sh BUILD_DIR [PATHS] [RUNS]
# Writes tests/bench/results/accuracy/pathtracer_cost.csv: per scene the tracer's time and noise
# at PATHS paths, the bake's time, its error (rms_all of concavity.csv's bounces-auto row,
# measured against a 32M-path reference with its noise removed), the tracer's time to that error
# and to 3 % (t_N (noise_N / e)^2), and the ratios; cpu_s: the tracer's 2 threads' CPU seconds.
# About 3 minutes on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: pathtracer_cost.sh BUILD_DIR [PATHS] [RUNS]}")
paths=${2:-2000000}
runs=${3:-3}
out=$root/tests/bench/results/accuracy
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bash "$root/data/fetch.sh" >/dev/null
"$build/tests/bench/pathtracer_cost" "$work" --paths "$paths" --runs "$runs"
python3 - "$work/tracer.csv" "$out/concavity.csv" "$out/pathtracer_cost.csv" <<'PY'
import csv, sys
tracer = list(csv.DictReader(open(sys.argv[1])))
bake_error = {r["scene"]: float(r["rms_all"]) for r in csv.DictReader(open(sys.argv[2]))
              if r["bounces_asked"] == "auto"}
with open(sys.argv[3], "w") as f:
    f.write("scene,paths,tracer_s,tracer_noise,bake_s,bounces,bake_error,tracer_s_at_bake_error,"
            "speedup_at_bake_error,tracer_s_at_3pct,speedup_at_3pct,tracer_cpu_s_at_1p7pct\n")
    for r in tracer:
        t, noise, bake = float(r["tracer_s"]), float(r["tracer_noise"]), float(r["bake_s"])
        e = bake_error[r["scene"]]
        at = lambda err: t * (noise / err) ** 2
        f.write(f'{r["scene"]},{r["paths"]},{t:.3f},{noise:.5f},{bake:.3f},{r["bounces"]},'
                f'{e:.5f},{at(e):.1f},{at(e) / bake:.0f},{at(0.03):.1f},{at(0.03) / bake:.0f},'
                f'{2 * at(0.017):.0f}\n')
PY
cat "$out/pathtracer_cost.csv"
