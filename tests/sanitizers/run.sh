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
# -O1 -g1: line numbers in the reports, and the build half the time of -O2 -g (instrumented code
# compiles 2-5 times slower than Release: measured on sss_bake_tool_test.cpp, 23 s of CPU against
# 54 s). No benchmarks: they are not tests.
flags="-O1 -g1 -DNDEBUG"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_FLAGS_RELWITHDEBINFO="$flags" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="$flags" -DSSS_SANITIZE=ON -DSSS_BUILD_TESTS=ON \
  -DSSS_BUILD_BENCHMARKS=OFF
cmake --build "$build" -j "$jobs"
# Mesa's llvmpipe driver leaks a few objects and is unloaded by eglTerminate, after which LSan can
# no longer name the library they came from (nor match a suppression): loaded with the program it
# stays mapped to the end, where its memory is still reachable. ASan's runtime must come first.
driver=$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -1 || true)
if [[ -n $driver ]]; then
  asan=$(ldd "$build/tests/render/render_test" | awk '/libasan/ { print $3 }')
  export LD_PRELOAD="${asan:+$asan:}$driver"
fi
ctest --test-dir "$build" --output-on-failure --no-tests=error -j "$jobs"
