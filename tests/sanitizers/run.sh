#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (with LeakSanitizer):
# builds with SSS_SANITIZE=ON into BUILD_DIR (default build-sanitize/; the compiler is CMake's
# default, GCC on Debian) and runs every test through ctest with the settings of env.sh. Exits
# non-zero when a test fails or a sanitizer reports (a report ends the process that made it).
#   tests/sanitizers/run.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath -m "${1:-$root/build-sanitize}")
cd "$root"
jobs=$(nproc)

# The settings hold for the build too: it runs the test programs to list their tests.
source tests/sanitizers/env.sh
# RelWithDebInfo: optimized as the Release suite is (the tests stay fast), with line numbers in
# the reports. No benchmarks: they are not tests.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSSS_SANITIZE=ON -DSSS_BUILD_TESTS=ON \
  -DSSS_BUILD_BENCHMARKS=OFF
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure --no-tests=error -j "$jobs"
