#!/usr/bin/env bash
# The checked build shared by the sanitizer suite (tests/sanitizers/run.sh) and the fuzz targets
# (tests/fuzz/run.sh): clang with AddressSanitizer + UndefinedBehaviorSanitizer (LeakSanitizer
# included) and, on the readers' libraries only, libFuzzer's coverage instrumentation (SSS_FUZZ=ON;
# CMakeLists.txt says why not everywhere), so one build serves both, and CI pays for one
# instrumented build instead of two. Builds TARGETS (default: everything) into
# BUILD_DIR.
#   tests/sanitizers/build.sh BUILD_DIR [TARGET ...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath -m "$1")
shift
cd "$root"

command -v clang++ >/dev/null || {
  echo "checked build: error: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
}
# -O1 (the usual libFuzzer build, and tests that still finish), assertions on (glm checks its
# indices), line tables only: reports name files and lines, at a fraction of -g's compile time.
flags="-O1 -gline-tables-only"
cmake -S . -B "$build" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Checked -DCMAKE_C_FLAGS_CHECKED="$flags" -DCMAKE_CXX_FLAGS_CHECKED="$flags" \
  -DSSS_FUZZ=ON -DSSS_BUILD_TESTS=ON -DSSS_BUILD_BENCHMARKS=OFF >/dev/null
targets=()
(($# > 0)) && targets=(--target "$@")
cmake --build "$build" -j "$(nproc)" "${targets[@]}"
