#!/usr/bin/env bash
# The Snakemake workflow (tools/workflow) on the three-row sample manifest: the dry run plans every
# job, the real run writes every output (bakes, renders, one CSV line per row, a contact sheet of
# the three renders), a second dry run finds nothing to do, and a changed mesh reruns only its
# row's bake and render and the gathering steps. Quick settings: no shadow rays, 5% tolerance,
# 96x96 renders.
# Usage: workflow_test.sh SOURCE_DIR BINARY_DIR
set -euo pipefail
src=$1 bin=$2/tools
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "workflow_test: FAIL: $*" >&2; exit 1; }

# The sample manifest with its paths made absolute (snakemake runs in the scratch folder), and
# the meshes copied there so that touching one does not touch the repository's data.
mkdir -p "$work/meshes"
{
  IFS= read -r header
  echo "$header"
  while IFS=, read -r mesh units material env rotation; do
    cp "$src/$mesh" "$work/meshes/"
    echo "$work/meshes/$(basename "$mesh"),$units,$material,$src/$env,$rotation"
  done
} <"$src/tools/workflow/sample_manifest.csv" >"$work/manifest.csv"

run() {
  snakemake -s "$src/tools/workflow/Snakefile" -d "$work" --config manifest="$work/manifest.csv" \
    out="$work/out" bin="$bin" bake_args="--visibility none --tolerance 0.05" \
    render_args="--size 96x96" "$@"
}
planned() { run -n --quiet 2>&1 | awk '$1 == "total" {print $2}'; }

n=$(planned)
[[ $n == 11 ]] || fail "dry run plans $n jobs, expected 11 (2 irrmap, 3 bake, 3 render, gather, sheet, all)"
run -j 2 --quiet >"$work/log" 2>&1 || { cat "$work/log"; fail "the real run failed"; }

for row in bunny_marble_forest_0 teapot_skin1_forest_90 dragon_res4_ketchup_studio_0; do
  for f in bake/$row.ply bake/$row.json render/$row.png render/$row.json; do
    [[ -s $work/out/$f ]] || fail "missing $f"
  done
done
for env in forest studio; do [[ -s $work/out/env/${env}_radiance.exr ]] || fail "missing $env"; done
lines=$(wc -l <"$work/out/reports.csv")
[[ $lines == 4 ]] || fail "reports.csv has $lines lines, expected a header and 3 rows"
head -1 "$work/out/reports.csv" | grep -q "bake.environment.rotate_deg" || fail "no bake columns"
head -1 "$work/out/reports.csv" | grep -q "irrmap.method" || fail "no irrmap columns"
python3 - "$work/out/reports.csv" <<'PY' || fail "reports.csv does not carry each row's rotation"
import csv, sys
rows = {r["name"]: r for r in csv.DictReader(open(sys.argv[1]))}
assert float(rows["teapot_skin1_forest_90"]["bake.environment.rotate_deg"]) == 90
assert float(rows["teapot_skin1_forest_90"]["render.environment_rotate_deg"]) == 90
assert float(rows["bunny_marble_forest_0"]["bake.environment.rotate_deg"]) == 0
PY
size=$(oiiotool --info "$work/out/contact_sheet.png" | sed -E 's/.*: *([0-9]+) x +([0-9]+),.*/\1x\2/')
[[ $size == "304x96" ]] || fail "contact sheet is $size, expected 3 renders of 96 with 8 px gaps"

n=$(planned)
[[ -z $n ]] || fail "up-to-date outputs were planned again ($n jobs)"
# A changed mesh (a header comment added: Snakemake 7 reruns for a newer input only when its
# content changed, not for a touch alone) reruns its own row only.
sleep 1
python3 - "$work/meshes/teapot.ply" <<'PY'
import sys
data = open(sys.argv[1], "rb").read()
second = data.index(b"\n", data.index(b"\n") + 1) + 1  # after "ply" and "format ..."
open(sys.argv[1], "wb").write(data[:second] + b"comment changed\n" + data[second:])
PY
n=$(planned)
[[ $n == 5 ]] || fail "a changed mesh plans $n jobs, expected 5 (its bake and render, gather, sheet, all)"

# Batches (plans only; slurm_test compares a batched run's outputs with batch=1's): with the
# teapot and the dragon added under forest in marble at the bunny's size, the three share a bake
# job and a render job; batch=2 splits them into two jobs of each, batch=1 gives one per row.
cp "$work/manifest.csv" "$work/batches.csv"
for mesh in teapot dragon_res4; do
  echo "$src/data/cache/meshes/$mesh.ply,size:120,marble,$src/data/cache/env/forest.exr,0"
done >>"$work/batches.csv"
# The bake and the render jobs a dry run with batch=$1 plans.
jobs_of() {
  snakemake -s "$src/tools/workflow/Snakefile" -d "$work/batches" -n --quiet \
    --config manifest="$work/batches.csv" out="$work/batches/out" bin="$bin" batch="$1" 2>&1 |
    awk '$1 == "total" {exit} $1 ~ /^bake_[0-9]+$/ {b += $2} $1 ~ /^render_[0-9]+$/ {r += $2}
         END {print b + 0, r + 0}'
}
for batch in 16 2 1; do
  expected=$((batch == 16 ? 3 : batch == 2 ? 4 : 5)) # the 3 rows in 1, 2 or 3 jobs; 2 rows alone
  n=$(jobs_of "$batch")
  [[ $n == "$expected $expected" ]] ||
    fail "batch=$batch plans '$n' bake and render jobs for 5 rows, expected $expected of each"
done
echo "workflow_test: ok"
