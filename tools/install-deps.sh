#!/usr/bin/env bash
# Installs the Debian 12 packages that building, testing and the sample data need, only those that
# are absent (a package counts as present when installed or provided by an installed package, e.g.
# npm by a nodejs build that bundles it). Runs as root, or through sudo otherwise.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git lld # toolchain (CMake >= 3.25; lld links faster)
  libopenmesh-dev libembree-dev libglm-dev libopenimageio-dev libopenexr-dev libpng-dev
  libcli11-dev nlohmann-json3-dev
  libopengl-dev libegl-dev libgl1-mesa-dri # OpenGL + EGL (glvnd) and Mesa's drivers (llvmpipe)
  libgtest-dev libbenchmark-dev gnuplot-nox python3 # tests (python3: tests/docs), benchmarks, charts
  help2man     # the man pages (tools/CMakeLists.txt)
  assimp-utils # tests: a second glTF reader for the baked GLB
  clang libclang-rt-14-dev # tests/fuzz: libFuzzer (clang's runtime) with ASan and UBSan
  npm ca-certificates xz-utils # data/fetch.sh: npm pack (node), apt-get download + dpkg-deb
  snakemake openimageio-tools  # tools/workflow: the Snakemake workflow and its contact sheet (oiiotool)
)

present=$(dpkg-query -W -f='${db:Status-Abbrev}|${Package}|${Provides}\n' 2>/dev/null |
  awk -F'|' '$1 ~ /^ii/ {
    print $2
    n = split($3, provided, /, */)
    for (i = 1; i <= n; ++i) {
      sub(/ .*/, "", provided[i])  # drop a version: "foo (= 1.0)"
      if (provided[i] != "") print provided[i]
    }
  }' | sort -u)
missing=()
for package in "${packages[@]}"; do
  grep -qxF "$package" <<<"$present" || missing+=("$package")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "install-deps: all ${#packages[@]} packages are present"
  exit 0
fi

as_root=(env DEBIAN_FRONTEND=noninteractive)
if [[ $EUID -ne 0 ]]; then
  command -v sudo >/dev/null || {
    echo "install-deps: error: not root and no sudo; as root run: apt-get install ${missing[*]}" >&2
    exit 1
  }
  as_root=(sudo "${as_root[@]}")
fi
echo "install-deps: installing ${missing[*]}"
"${as_root[@]}" apt-get update -q
"${as_root[@]}" apt-get install -y -q "${missing[@]}"
