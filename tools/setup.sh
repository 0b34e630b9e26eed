#!/usr/bin/env bash
# Command 1: install the missing Debian packages the tools need (tools/install-deps.sh, without the
# tests'), fetch the sample data, build the tools only (Release, no tests or benchmarks) into
# build/ (SSS_BUILD_DIR overrides) and run the default pipeline, which writes its pictures to out/.
# Prints the time of each step.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${SSS_BUILD_DIR:-build}

start=$SECONDS
step_done() {
  echo "setup: $1 in $((SECONDS - start)) s"
  start=$SECONDS
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
