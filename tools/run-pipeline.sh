#!/usr/bin/env bash
# The default pipeline (run by command 1): environment -> cubemaps (sss-irrmap, on the sample
# environment forest.exr and on the procedural --sky), marble bunny baked under forest.exr
# (sss-bake), rendered to a PNG (sss-render); then the paper's figures (tools/paper-figures.sh,
# into out/paper; Table 1, a benchmark, only with SSS_TABLE=1). Writes everything to out/ and
# lists the pictures.
# Needs a Release build in build/ (SSS_BUILD_DIR overrides) and data/fetch.sh's sample data.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bin=${SSS_BUILD_DIR:-build}/tools
out=out
env=data/cache/env/forest.exr
mesh=data/cache/meshes/bunny.ply
bunny_mm_per_unit=15 # the npm bunny is about 10 units long: 150 mm of marble

for file in "$env" "$mesh"; do
  [[ -f $file ]] || {
    echo "run-pipeline: error: $file is missing: run data/fetch.sh" >&2
    exit 1
  }
done
mkdir -p "$out"
started=$(mktemp)
trap 'rm -f "$started"' EXIT

# Runs tool ARGS... from the build.
run() {
  local tool=$1
  shift
  if [[ ! -x $bin/$tool ]]; then
    echo "run-pipeline: error: $bin/$tool is missing: build it (tools/setup.sh)" >&2
    exit 1
  fi
  echo "+ $tool $*"
  "$bin/$tool" "$@"
}

run sss-irrmap "$env" --radiance "$out/forest_radiance.exr" -o "$out/forest_irradiance.exr" \
  --json "$out/forest_irrmap.json"
run sss-irrmap --sky --radiance "$out/sky_radiance.exr" -o "$out/sky_irradiance.exr" \
  --json "$out/sky_irrmap.json"
# --bounces auto: the bunny's ears, chin and haunch send each other light (without it the bake
# warns that B would change by ~9 %; docs/physics.md, "Light the object sends itself").
run sss-bake "$mesh" -e "$env" -m marble --mm-per-unit "$bunny_mm_per_unit" --bounces auto \
  -o "$out/bunny_marble.ply" --json "$out/bunny_marble_bake.json"
run sss-render "$out/bunny_marble.ply" -e "$env" -o "$out/bunny_marble.png" --exposure -1
SSS_BUILD_DIR=${SSS_BUILD_DIR:-build} bash tools/paper-figures.sh "$out/paper"

echo "Pictures in $(pwd)/$out:"
find "$out" -name '*.png' -newer "$started" | sort | while read -r picture; do
  echo "  $picture"
done
