#!/usr/bin/env bash
# A texture-baked GLB as a stock web viewer shows it: a UV sphere (marble, 40 mm) baked with
# `sss-bake --texture 256 -o sphere.glb` under forest.exr, opened with three.js's stock GLTFLoader
# in the viewer page (tools/viewer/index.html) in headless Chromium (WebGL2 on SwiftShader), the
# environment as background and light, sss-render's default camera. Passes when:
#   - the Khronos validator finds 0 errors and 0 warnings in the GLB;
#   - the page loads it without a console warning or error;
#   - the screenshot matches sss-render's picture of a per-vertex bake of the same sphere (same
#     view, no tone mapping) at PSNR >= 30 dB over the object's pixels (tests/browser/picture_psnr).
# Needs chromium and the npm packages of `data/fetch.sh --tests` (three.js, the validator).
# Usage: browser_test.sh SOURCE_DIR BINARY_DIR
# The benchmark tests/bench/browser_check.sh runs it on other cases through the environment:
# SSS_BROWSER_ENV (a sample environment's name, default forest), SSS_BROWSER_MATERIAL (default
# marble), SSS_BROWSER_GLB (texture, or vertex: sss-bake's vertex-colour GLB) and
# SSS_BROWSER_MIN_PSNR (default 30).
set -euo pipefail
src=$1 bin=$2
work=$(mktemp -d)
server=
cleanup() {
  [[ -n $server ]] && kill "$server" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "browser_test: FAIL: $*" >&2; exit 1; }
three=$src/data/cache/npm/three
env_name=${SSS_BROWSER_ENV:-forest}
material=${SSS_BROWSER_MATERIAL:-marble}
kind=${SSS_BROWSER_GLB:-texture}
min_psnr=${SSS_BROWSER_MIN_PSNR:-30}
env=$src/data/cache/env/$env_name.exr
[[ -f $three/build/three.module.js ]] || fail "no three.js in $three: run data/fetch.sh --tests"
[[ -f $env ]] || fail "no $env: run data/fetch.sh"
bake() { "$bin/tools/sss-bake" "$work/sphere.glb" -e "$env" -m "$material" --seed 1 --quiet "$@"; }
render() {
  "$bin/tools/sss-render" "$work/vertex.ply" -e "$env" --size 512x512 --tonemap none --quiet "$@"
}

mkdir "$work/site"
"$bin/tests/browser/uv_sphere_asset" "$work/sphere.glb" 96 48 0.02
case $kind in
  texture) bake --texture 256 -o "$work/site/sphere.glb" ;;
  vertex) bake -o "$work/site/sphere.glb" ;;
  *) fail "SSS_BROWSER_GLB=$kind: texture or vertex" ;;
esac
bake -o "$work/vertex.ply"
node "$src/tests/mesh/validate_gltf.js" "$work/site/sphere.glb" | tee "$work/validator.log"
grep -q ": 0 errors, 0 warnings," "$work/validator.log" || fail "the validator finds problems"
render -o "$work/render.png"
render --background 0,0,0 -o "$work/on_black.png"
render --background 1,1,1 -o "$work/on_white.png"

# The page as shipped, three.js from the local copy instead of the CDN.
sed 's|https://cdn.jsdelivr.net/npm/three@[0-9.]*/|/three/|g' "$src/tools/viewer/index.html" \
  >"$work/site/index.html"
ln -s "$three" "$work/site/three"
ln -s "$env" "$work/site/env.exr"
python3 -m http.server 0 --bind 127.0.0.1 --directory "$work/site" >"$work/server.log" 2>&1 &
server=$!
port=
for _ in $(seq 50); do
  port=$(grep -o 'port [0-9]*' "$work/server.log" | cut -d' ' -f2 || true)
  [[ -n $port ]] && break
  sleep 0.1
done
[[ -n $port ]] || fail "the HTTP server did not start: $(cat "$work/server.log")"

chromium --headless=new --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader \
  --hide-scrollbars --force-device-scale-factor=1 --window-size=512,512 \
  --virtual-time-budget=30000 --enable-logging=stderr --v=0 --user-data-dir="$work/profile" \
  --screenshot="$work/shot.png" \
  "http://127.0.0.1:$port/index.html?model=sphere.glb&env=env.exr&size=512" \
  2>"$work/chromium.log" || { tail -5 "$work/chromium.log"; fail "chromium failed"; }
grep 'CONSOLE' "$work/chromium.log" || true
grep -q 'viewer: ready' "$work/chromium.log" || fail "the page did not report ready"
if grep 'CONSOLE' "$work/chromium.log" | grep -qiE 'warn|error'; then
  fail "the page logged a warning or an error"
fi
[[ -s $work/shot.png ]] || fail "no screenshot"

result=$("$bin/tests/browser/picture_psnr" "$work/shot.png" "$work/render.png" \
  "$work/on_black.png" "$work/on_white.png")
echo "browser_test: $result"
psnr=$(sed 's/.*psnr_db=\([0-9.]*\).*/\1/' <<<"$result")
awk -v p="$psnr" -v m="$min_psnr" 'BEGIN { exit !(p >= m) }' ||
  fail "PSNR $psnr dB against sss-render, under $min_psnr"
echo "browser_test: passed"
