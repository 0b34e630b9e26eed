#!/usr/bin/env bash
# The paper end to end (Li & Guo): Figure 3 (the same marble model, BRDF vs our method),
# Figure 4 (the teapot in an environment, with reflections) and, with --table, Table 1 (triangles
# and FPS at 1024x1024 for the dragon at four resolutions, the teapot and the bunny), from the
# sample data of data/fetch.sh: sss-bake, then sss-render.
#
#   tools/paper-figures.sh [--table] [OUT_DIR]   (default out/paper; tests/bench/results/render
#                                                 holds the copy docs/performance.md shows)
#
# Writes OUT_DIR/figure3_brdf.png, figure3_sss.png, figure4_teapot.png and
# figure4_teapot_paper_mix.png; with --table (or SSS_TABLE=1) also table1.csv, table1.md and
# table1_fps.png. Table 1 is a benchmark (six bakes, the 871K-triangle dragon among them, and
# timed 1024x1024 frames: minutes of CPU), so the default pipeline of command 1 leaves it out.
# The baked meshes go to ${SSS_WORK_DIR:-out/paper-work}. Needs a Release build in build/
# (SSS_BUILD_DIR overrides). SSS_TABLE_FRAMES (default 20) sets the timed frames per model.
#
# Table 1 is measured the way a real-time renderer draws: one sample per pixel (no MSAA: on
# llvmpipe 4x MSAA costs about twice the time), back faces culled, the environment behind the
# model, glFinish after every frame, median over the frames. Every FPS comes with the GL
# renderer that measured it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

table=${SSS_TABLE:-0}
if [[ ${1:-} == --table ]]; then
  table=1
  shift
fi
bin=${SSS_BUILD_DIR:-build}/tools
out=${1:-out/paper}
work=${SSS_WORK_DIR:-out/paper-work}
frames=${SSS_TABLE_FRAMES:-20}
meshes=data/cache/meshes
envs=data/cache/env

for tool in sss-bake sss-render; do
  [[ -x $bin/$tool ]] || {
    echo "paper-figures: error: $bin/$tool is missing: build it first" >&2
    exit 1
  }
done
for file in $meshes/{dragon_res4,dragon_res3,dragon_res2,dragon,teapot,bunny}.ply \
  $envs/{forest,city}.exr; do
  [[ -f $file ]] || {
    echo "paper-figures: error: $file is missing: run data/fetch.sh" >&2
    exit 1
  }
done
mkdir -p "$out" "$work"

# bake NAME MESH ENV: marble, 150 mm along the longest side (sss-bake's defaults otherwise).
bake() {
  local baked=$work/$1.ply
  if [[ ! -f $baked || $baked -ot $2 || $baked -ot $bin/sss-bake ]]; then
    echo "+ sss-bake $2 -e $3 -m marble --size-mm 150 -o $baked"
    "$bin/sss-bake" "$2" -e "$3" -m marble --size-mm 150 -o "$baked" --quiet
  fi
}
render() {
  echo "+ sss-render $*"
  "$bin/sss-render" "$@" --quiet
}

# Figure 3: the same marble dragon (47K triangles; the paper's Buddha has 78K), a Lambertian
# BRDF with the marble's total diffuse reflectance vs the baked subsurface exitance.
bake dragon_res3 $meshes/dragon_res3.ply $envs/forest.exr
for mode in brdf sss; do
  render "$work/dragon_res3.ply" -e $envs/forest.exr -o "$out/figure3_$mode.png" --mode $mode \
    --size 768x768 --samples 4 --exposure -1 --azimuth 30 --elevation 10
done

# Figure 4: the teapot in a city, Fresnel reflections; and the paper's constant mix (0.3).
bake teapot_city $meshes/teapot.ply $envs/city.exr
render "$work/teapot_city.ply" -e $envs/city.exr -o "$out/figure4_teapot.png" \
  --size 768x768 --samples 4 --exposure -1.25 --azimuth 40 --elevation 20
render "$work/teapot_city.ply" -e $envs/city.exr -o "$out/figure4_teapot_paper_mix.png" \
  --size 768x768 --samples 4 --exposure -1.25 --azimuth 40 --elevation 20 --reflect-factor 0.3

if [[ $table != 1 ]]; then
  echo "paper-figures: wrote $out/{figure3_brdf,figure3_sss,figure4_teapot,figure4_teapot_paper_mix}.png (Table 1: tools/paper-figures.sh --table)"
  exit 0
fi

# Table 1.
# Values from sss-render's --json (pretty-printed: one key per line).
json_value() { sed -n "s/^ *\"$1\": \([^\"][^,]*\),\{0,1\}$/\1/p" "$2" | head -n 1; }
json_string() { sed -n "s/^ *\"$1\": \"\(.*\)\",\{0,1\}$/\1/p" "$2" | head -n 1; }
csv=$out/table1.csv
echo "model,triangles,vertices,width,height,samples,cull,median_ms,fps,pipelined_fps,min_ms,max_ms,cpu_ms,renderer" >"$csv.tmp"
for model in dragon_res4 dragon_res3 dragon_res2 dragon teapot bunny; do
  bake "$model" $meshes/$model.ply $envs/forest.exr
  report=$work/$model-frames.json
  render "$work/$model.ply" -e $envs/forest.exr -o "$work/$model-frames.png" --size 1024x1024 \
    --samples 1 --cull back --frames "$frames" --warmup 3 --json "$report"
  median=$(json_value median_ms "$report")
  pipelined=$(json_value pipelined_ms "$report")
  printf '%s,%s,%s,1024,1024,1,back,%.2f,%.1f,%.1f,%.2f,%.2f,%.2f,"%s"\n' "$model" \
    "$(json_value triangles "$report")" "$(json_value vertices "$report")" "$median" \
    "$(json_value fps "$report")" "$(awk -v p="$pipelined" 'BEGIN { printf "%.1f", 1000 / p }')" \
    "$(json_value min_ms "$report")" "$(json_value max_ms "$report")" \
    "$(json_value cpu_ms "$report")" "$(json_string renderer "$report")" >>"$csv.tmp"
done
mv "$csv.tmp" "$csv"

renderer=$(json_string renderer "$work/bunny-frames.json")
cores=$(nproc)
{
  echo "# Table 1: triangles and frames per second at 1024x1024"
  echo
  echo "Measured by \`tools/paper-figures.sh\` with \`sss-render --frames $frames --samples 1 --cull back\`"
  echo "(environment background, glFinish after each frame, median of the frames) on"
  echo "**$renderer** ($cores CPU cores visible to the process), $(date -u +%Y-%m-%d)."
  echo
  echo "| Model | Triangles | ms/frame (median) | FPS | FPS, frames pipelined | CPU ms/frame, all threads |"
  echo "| --- | ---: | ---: | ---: | ---: | ---: |"
  tail -n +2 "$csv" | while IFS=, read -r model tris _ _ _ _ _ median fps pipelined _ _ cpu _; do
    echo "| $model | $tris | $median | $fps | $pipelined | $cpu |"
  done
  echo
  echo "On a software renderer the wall clock depends on what else the machine runs; the CPU"
  echo "time of all the renderer's threads does not, and bounds the idle wall time from below"
  echo "by CPU / cores."

  echo
  echo "The paper (GeForce 9800GT): Buddha 78K triangles 65 FPS, teapot 46K triangles 83 FPS."
} >"$out/table1.md"
# Frames per second against triangles (log-log), from the CSV. gnuplot is a test dependency
# (tools/install-deps.sh --tests), not the tools'.
chart=", table1_fps.png"
if ! command -v gnuplot >/dev/null; then
  chart=" (no table1_fps.png: gnuplot is not installed)"
else
  gnuplot <<GNUPLOT
set terminal pngcairo size 720,480 font ",11" noenhanced
set output "$out/table1_fps.png"
set datafile separator ","
set logscale xy
set grid
set key off
set xlabel "triangles"
set ylabel "frames per second at 1024x1024"
set title "sss-render on $renderer"
set label "target for 200K triangles: 20 FPS" at first 1200, first 23 font ",9"
plot "$csv" skip 1 using 2:9 with points pt 7 ps 1.5, \\
     "" skip 1 using 2:9:1 with labels offset 0,1 font ",9", \\
     20 with lines dt 2 lc rgb "gray"
GNUPLOT
fi
echo "paper-figures: wrote $out/{figure3_brdf,figure3_sss,figure4_teapot,figure4_teapot_paper_mix}.png, table1.csv, table1.md$chart"
