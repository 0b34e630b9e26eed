#!/usr/bin/env bash
# The Snakemake workflow on many assets: 3 meshes (teapot, bunny, dragon_res4; 150 mm) x 3
# material presets (marble, skin1, ketchup) x the 8 sample environments = 72 rows, on this
# machine with `-j 2`, once with one bake and one render job per row (batch=1) and once with the
# workflow's batches (a bake job per environment and material: 3 rows; a render job per
# environment: 9 rows). Measures each run's wall clock and CPU time (Snakemake and every job),
# and reports bakes (rows: a bake and its render) per hour per core: per core of the 2 that -j
# gives (wall) and per core-hour actually used (CPU; the machine may be shared). The 1-minute
# load average before and after each run is recorded. The environments' cubemaps (sss-irrmap, the
# same in both runs) are made once beforehand and not counted. Both runs' bakes and renders must
# be byte-identical.
# Bake options: a 5 % tolerance, far field and unscattered light off (they cost up to 20 s per
# small ketchup object; the per-job costs batching saves are the same either way). Renders:
# the workflow's default 512x512.
# Usage: tests/bench/workflow_throughput.sh [BUILD_DIR] [BATCH=16] [RUNS=1] [ENVIRONMENTS=8]
#   RUNS: pairs of runs, alternating the modes (the CSV keeps each run); ENVIRONMENTS: the first N
#   sample environments only (a quick check of the script: 9 rows each).
# Output: tests/bench/results/workflow/throughput.csv, throughput.png
# Needs the sample data (data/fetch.sh; SSS_DATA_CACHE), snakemake, oiiotool and gnuplot.
# Takes ~5 min of CPU per run at 2 cores (~25 min per run on a machine shared 4 ways).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
batch=${2:-16}
runs=${3:-1}
environments=${4:-8}
data=${SSS_DATA_CACHE:-$root/data/cache}
results=$root/tests/bench/results/workflow
jobs=2
bake_args="--tolerance 0.05 --far-field off --unscattered off"
meshes=(teapot bunny dragon_res4)
materials=(marble skin1 ketchup)
mkdir -p "$results"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

envs=("$data"/env/*.exr)
[[ ${#envs[@]} == 8 && -f $data/meshes/bunny.ply ]] || { echo "missing sample data: run data/fetch.sh" >&2; exit 1; }
envs=("${envs[@]:0:$environments}")
{
  echo "mesh,units,material,environment,rotation"
  for env in "${envs[@]}"; do
    for material in "${materials[@]}"; do
      for mesh in "${meshes[@]}"; do echo "$data/meshes/$mesh.ply,size:150,$material,$env,0"; done
    done
  done
} >"$tmp/manifest.csv"
rows=$(($(wc -l <"$tmp/manifest.csv") - 1))

# Usage: workflow FOLDER BATCH [SNAKEMAKE OPTIONS AND TARGETS...] (before --config, which takes
# every word after it)
workflow() {
  local folder=$1 size=$2
  shift 2
  snakemake -s "$root/tools/workflow/Snakefile" -d "$folder" -j "$jobs" "$@" \
    --config manifest="$tmp/manifest.csv" out="$folder/out" bin="$build/tools" batch="$size" \
    bake_args="$bake_args"
}

# The cubemaps once; each run starts from a copy (Snakemake takes files without a record of
# their own as up to date).
env_targets=()
for env in "${envs[@]}"; do env_targets+=("$tmp/envs/out/env/$(basename "${env%.*}")_radiance.exr"); done
workflow "$tmp/envs" 1 "${env_targets[@]}" >"$tmp/envs.log" 2>&1 ||
  { cat "$tmp/envs.log" >&2; exit 1; }

# Seconds of wall clock and of CPU (user + system of the waited-for children: Snakemake and every
# job it ran) of "$@", as tests/bench/batch_bench.sh measures.
measure() {
  local start end cpu0 cpu1 self=$BASHPID
  cpu0=$(awk '{print $14 + $15 + $16 + $17}' "/proc/$self/stat")
  start=$(date +%s.%N)
  "$@" >/dev/null 2>&1
  end=$(date +%s.%N)
  cpu1=$(awk '{print $14 + $15 + $16 + $17}' "/proc/$self/stat")
  awk -v s="$start" -v e="$end" -v c0="$cpu0" -v c1="$cpu1" -v hz="$(getconf CLK_TCK)" \
    'BEGIN {printf "%.2f %.2f\n", e - s, (c1 - c0) / hz}'
}
load() { cut -d' ' -f1 /proc/loadavg; }
# The number of jobs of the rules matching $2 in a dry run's (first) job table ($1).
planned() { awk -v rule="$2" '$1 == "total" {exit} $1 ~ rule {n += $2} END {print n + 0}' "$1"; }

csv=$results/throughput.csv
{
  echo "# tests/bench/workflow_throughput.sh: $rows rows (teapot, bunny, dragon_res4 at 150 mm x marble, skin1, ketchup x ${#envs[@]} environments), snakemake -j $jobs, bake_args '$bake_args', renders 512x512; $(nproc) cores"
  echo "mode,run,batch,rows,bake_jobs,render_jobs,wall_s,cpu_s,cores,load_before,load_after,bakes_per_hour_per_core,bakes_per_core_hour_cpu"
} >"$csv"
for run in $(seq 1 "$runs"); do
  for mode in unbatched batched; do
    size=1
    [[ $mode == batched ]] && size=$batch
    folder=$tmp/$mode-$run
    rm -rf "$folder" && mkdir -p "$folder/out"
    cp -a "$tmp/envs/out/env" "$folder/out/"
    workflow "$folder" "$size" -n >"$folder.plan" 2>&1
    [[ $(planned "$folder.plan" '^irrmap$') == 0 ]] || { echo "the cubemaps would be redone" >&2; exit 1; }
    bake_jobs=$(planned "$folder.plan" '^bake_[0-9]+$')
    render_jobs=$(planned "$folder.plan" '^render_[0-9]+$')
    before=$(load)
    read -r wall cpu < <(measure workflow "$folder" "$size")
    after=$(load)
    [[ -s $folder/out/reports.csv && -s $folder/out/contact_sheet.png ]] ||
      { echo "$mode run $run did not finish" >&2; exit 1; }
    awk -v m="$mode" -v r="$run" -v b="$size" -v n="$rows" -v bj="$bake_jobs" -v rj="$render_jobs" \
      -v w="$wall" -v c="$cpu" -v j="$jobs" -v l0="$before" -v l1="$after" 'BEGIN {
        printf "%s,%d,%d,%d,%d,%d,%.1f,%.1f,%d,%.2f,%.2f,%.0f,%.0f\n", m, r, b, n, bj, rj, w, c, j,
               l0, l1, n * 3600 / (w * j), n * 3600 / c
      }' | tee -a "$csv"
  done
done

# Batches change no output: every bake and render byte for byte.
for f in "$tmp/unbatched-1/out"/{bake/*.ply,render/*.png}; do
  cmp -s "$f" "$tmp/batched-1/out/${f#"$tmp/unbatched-1/out/"}" ||
    { echo "workflow_throughput: $(basename "$f") differs between batch=1 and batch=$batch" >&2; exit 1; }
done

# Throughput by mode: medians over the runs (one bar each for wall and CPU).
python3 - "$csv" >"$tmp/chart.dat" <<'PY'
import csv, statistics, sys
lines = [l for l in open(sys.argv[1]) if not l.startswith("#")]
runs = list(csv.DictReader(lines))
for mode, label in (("unbatched", "one job per row"), ("batched", "batches")):
    chosen = [r for r in runs if r["mode"] == mode]
    wall = statistics.median(float(r["bakes_per_hour_per_core"]) for r in chosen)
    cpu = statistics.median(float(r["bakes_per_core_hour_cpu"]) for r in chosen)
    print(f'"{label}" {wall} {cpu}')
PY
gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced font ",11"
set output "$results/throughput.png"
set title "Workflow, $rows rows (3 meshes x 3 materials x ${#envs[@]} environments), -j $jobs"
set ylabel "bakes (bake + render) per hour per core"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set yrange [0:*]
set grid ytics
set key top left
plot "$tmp/chart.dat" using 2:xtic(1) title "per core of the $jobs given (wall clock)", \
     "" using 3 title "per core-hour used (CPU time)"
GP
echo "wrote $csv and $results/throughput.png"
