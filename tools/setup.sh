#!/usr/bin/env bash
# Command 1: install the missing Debian packages the tools need (tools/install-deps.sh, without the
# tests'), fetch the sample data, build the tools only (Release, no tests or benchmarks) into
# build/ (SSS_BUILD_DIR overrides) and run the default pipeline, which writes its pictures to out/.
# Prints each step's wall time and CPU time (on a busy machine the wall time says little).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${SSS_BUILD_DIR:-build}

# CPU seconds of this script's finished children (apt, the compilers, the tools): fields 16-17 of
# /proc/PID/stat, in clock ticks of 1/100 s.
cpu_seconds() { awk '{ print int(($16 + $17) / 100) }' "/proc/$$/stat"; }
start=$SECONDS cpu_start=$(cpu_seconds)
step_done() {
  local cpu
  cpu=$(cpu_seconds)
  echo "setup: $1 in $((SECONDS - start)) s (CPU $((cpu - cpu_start)) s)"
  start=$SECONDS cpu_start=$cpu
}

bash tools/install-deps.sh
step_done packages
bash data/fetch.sh
step_done "sample data"
# Tests off: command 2 (tools/test.sh) turns them on in the same build folder; the libraries'
# objects are shared, so switching back and forth recompiles nothing.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DSSS_BUILD_TESTS=OFF -DSSS_BUILD_BENCHMARKS=OFF
cmake --build "$build" -j "$(nproc)"
step_done build
SSS_BUILD_DIR=$build bash tools/run-pipeline.sh
step_done pipeline
