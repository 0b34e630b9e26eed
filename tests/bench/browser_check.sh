#!/usr/bin/env bash
# What a stock web viewer shows of sss-bake's GLBs: tests/browser/browser_test.sh (a 40 mm UV
# sphere baked under a sample environment, opened with three.js's GLTFLoader in headless Chromium,
# the screenshot against sss-render's picture of the same view) for each sample environment, the
# marble and skin1 presets, and both GLBs: the texture bake (emission under a clear coat) and the
# vertex-colour bake (unlit COLOR_0).
#   tests/bench/browser_check.sh BUILD_DIR
# Writes tests/bench/results/browser/viewer_psnr.csv: env, material, glb, psnr_db (8-bit sRGB,
# the object's pixels), mean_abs (mean absolute difference, 8-bit levels), object_pixels.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath "${1:?usage: browser_check.sh BUILD_DIR}")
out=$root/tests/bench/results/browser
mkdir -p "$out"
csv=$out/viewer_psnr.csv
echo "env,material,glb,psnr_db,mean_abs,object_pixels" >"$csv.tmp"
for env in "$root"/data/cache/env/*.exr; do
  name=$(basename "$env" .exr)
  for material in marble skin1; do
    for glb in texture vertex; do
      line=$(SSS_BROWSER_ENV=$name SSS_BROWSER_MATERIAL=$material SSS_BROWSER_GLB=$glb \
        SSS_BROWSER_MIN_PSNR=0 bash "$root/tests/browser/browser_test.sh" "$root" "$build" 2>/dev/null |
        grep 'psnr_db=')
      psnr=$(sed 's/.*psnr_db=\([0-9.]*\).*/\1/' <<<"$line")
      mean=$(sed 's/.*mean_abs=\([0-9.]*\).*/\1/' <<<"$line")
      pixels=$(sed 's/.*object_pixels=\([0-9]*\).*/\1/' <<<"$line")
      echo "$name,$material,$glb,$psnr,$mean,$pixels" | tee -a "$csv.tmp"
    done
  done
done
mv "$csv.tmp" "$csv"
