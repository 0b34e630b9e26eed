#!/usr/bin/env bash
# The installed tools alone, from a folder outside the source and build trees: each tool's
# --version and sss-bake's --help, a quick bake of the sample bunny under the procedural sky and a
# 128x128 render of it in forest.exr. Checks the outputs (the PLY's vertex count, the PNG's
# signature and size, a TIFF through the OpenImageIO module), that no installed tool has an RPATH
# back into the source or build tree or links OpenImageIO, and that the man pages and the
# documentation are installed. Shared by install_test.sh (cmake --install) and deb_test.sh (the
# Debian package, extracted).
# Quick settings (~1 s for the bake): no shadow rays, 5 % tolerance, the half-space energy without
# the far field or the unscattered light (their random walks and light tracing are most of a bake
# at these sizes).
# Usage: check_installed.sh NAME PREFIX SOURCE_DIR BINARY_DIR MAN_PAGES(ON|OFF)
set -euo pipefail
name=$1 prefix=$2 src=$3 build=$4 man_pages=$5
fail() { echo "$name: FAIL: $*" >&2; exit 1; }

mesh=$src/data/cache/meshes/bunny.ply
env=$src/data/cache/env/forest.exr
for f in "$mesh" "$env"; do [[ -f $f ]] || fail "$f missing: run data/fetch.sh"; done
bin=$prefix/bin
tools=(sss-irrmap sss-bake sss-render sss-relight)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
for tool in "${tools[@]}"; do
  [[ -x $bin/$tool ]] || fail "$bin/$tool not installed"
  version=$("$bin/$tool" --version) || fail "$tool --version failed"
  [[ $version =~ ^$tool\ \(sss-tools\)\ [0-9] ]] || fail "$tool --version printed '$version'"
  # CMake strips the build tree's RPATH when installing; none must point back at either tree.
  dynamic=$(readelf -d "$bin/$tool") || fail "readelf -d $tool failed"
  rpath=$(grep -E 'R(UN)?PATH' <<<"$dynamic" || true)
  [[ $rpath != *"$build"* && $rpath != *"$src"* ]] || fail "$tool's RPATH names a tree: $rpath"
  # OpenImageIO is loaded when a format needs it (lib/image/image_format.h), never at start-up.
  ! grep -q 'NEEDED.*OpenImageIO' <<<"$dynamic" || fail "$tool links OpenImageIO"
done
help=$("$bin/sss-bake" --help) || fail "sss-bake --help failed"
grep -q '^Usage:' <<<"$help" || fail "sss-bake --help printed no usage"

"$bin/sss-bake" "$mesh" --sky -m marble --size-mm 150 --visibility none --tolerance 0.05 \
  --energy halfspace --far-field off --unscattered off -q -o bunny.ply || fail "the bake failed"
"$bin/sss-render" bunny.ply -e "$env" --env-size 32 --size 128x128 -q -o bunny.png ||
  fail "the render failed"

# A format only OpenImageIO writes, through the module installed beside the tools
# (<libdir>/sss-tools/sss_oiio.so, found from the executable's folder): TIFF's byte-order mark.
"$bin/sss-render" bunny.ply -e "$env" --env-size 32 --size 64x64 -q -o bunny.tif ||
  fail "the TIFF render failed (OpenImageIO's module not found?)"
[[ $(head -c 2 bunny.tif) == II || $(head -c 2 bunny.tif) == MM ]] || fail "bunny.tif is no TIFF"

# The baked PLY has the input's vertices, each with its exitance, and their data.
vertices=$(grep -a -m1 '^element vertex ' "$mesh" | tr -d '\r')
[[ -n $vertices ]] || fail "no vertex count in $mesh"
header=$(sed -n '1,/^end_header/p' bunny.ply)
grep -qx "$vertices" <<<"$header" || fail "bunny.ply's header lacks '$vertices'"
grep -qx 'property float exitance_r' <<<"$header" || fail "bunny.ply has no exitance"
size=$(stat -c %s bunny.ply)
((size > ${#header} + ${vertices##* } * 24)) || fail "bunny.ply is $size bytes, too small"

# The PNG: its signature, IHDR's width and height (big-endian, bytes 16-23), and more bytes than
# a flat picture compresses to (a few hundred; the bunny in the forest is ~16 KB).
[[ $(od -An -tx1 -N8 bunny.png | tr -d ' \n') == 89504e470d0a1a0a ]] || fail "bunny.png is no PNG"
dims=$(od -An -tu1 -j16 -N8 bunny.png |
  awk '{print $1*16777216 + $2*65536 + $3*256 + $4 "x" $5*16777216 + $6*65536 + $7*256 + $8}')
[[ $dims == 128x128 ]] || fail "bunny.png is $dims, expected 128x128"
(($(stat -c %s bunny.png) > 2000)) || fail "bunny.png is $(stat -c %s bunny.png) bytes: flat?"

if [[ $man_pages == ON ]]; then
  for tool in "${tools[@]}"; do
    page=$prefix/share/man/man1/$tool.1
    grep -q '^\.TH' "$page" 2>/dev/null || fail "no man page $page"
  done
fi
doc=$prefix/share/doc/sss-tools
for f in README.md LICENSE; do cmp -s "$src/$f" "$doc/$f" || fail "$doc/$f not installed"; done
cmp -s "$src/tools/viewer/index.html" "$doc/viewer/index.html" || fail "the viewer page not installed"
# Not in every checkout: installed when present.
for f in CHANGELOG.md docs; do
  [[ ! -e $src/$f || -e $doc/$f ]] || fail "$doc/$f not installed"
done
