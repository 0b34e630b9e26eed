#!/usr/bin/env bash
# Installs the Debian 12 packages that are absent (a package counts as present when installed or
# provided by an installed package, e.g. nodejs by a build that provides it), without their
# recommendations. Runs as root, or through sudo otherwise.
#   tools/install-deps.sh           building the tools, running them and fetching the sample data
#   tools/install-deps.sh --tests   and what the tests, the benchmarks and the workflow need
# docs/dependencies.md says what each package is for.
set -euo pipefail

packages=(
  g++ make cmake pkg-config lld # toolchain (CMake >= 3.25; lld links faster)
  libopenmesh-dev libembree-dev libglm-dev libopenimageio-dev libopenexr-dev libpng-dev
  libcli11-dev nlohmann-json3-dev
  libopengl-dev libegl-dev libgl1-mesa-dri # OpenGL + EGL (glvnd) and Mesa's drivers (llvmpipe)
  help2man                     # the man pages, installed with the tools (tools/CMakeLists.txt)
  nodejs ca-certificates       # data/fetch.sh: node (npm-fetch.js, the PLY converter; not npm)
)
test_packages=(
  libgtest-dev libbenchmark-dev python3 # the tests (python3: tests/docs) and the benchmarks
  assimp-utils             # tests/mesh: a second glTF reader for the baked GLB
  clang libclang-rt-14-dev # tests/fuzz, tests/sanitizers: libFuzzer (clang's runtime), ASan, UBSan
  snakemake openimageio-tools # tests/workflow: the Snakemake workflow and its contact sheet
  slurm-wlm munge          # tests/workflow/slurm_test.sh: a one-node Slurm for the Slurm profile
  dpkg-dev file            # tests/install: cpack -G DEB (dpkg-shlibdeps and file)
  gnuplot-nox              # the benchmarks' charts, Table 1's chart (tools/paper-figures.sh)
  chromium                 # tests/browser: our GLBs in a real browser (headless, WebGL2 in software)
)
case ${1:-} in
  '') ;;
  --tests) packages+=("${test_packages[@]}") ;;
  *)
    echo "install-deps: error: unknown option '$1' (usage: tools/install-deps.sh [--tests])" >&2
    exit 2
    ;;
esac

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
    echo "install-deps: error: not root and no sudo; as root run:" \
      "apt-get install --no-install-recommends ${missing[*]}" >&2
    exit 1
  }
  as_root=(sudo "${as_root[@]}")
fi
echo "install-deps: installing ${missing[*]}"
"${as_root[@]}" apt-get update -q
# Recommendations would bring hundreds more (Snakemake's and oiiotool's: cloud SDKs, GDAL, Qt).
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
