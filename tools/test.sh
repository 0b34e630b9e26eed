#!/usr/bin/env bash
# Command 2: fetch the sample data (cached), build Release into build/ (SSS_BUILD_DIR overrides)
# and run the whole test suite through ctest. Exits non-zero when a step or a test fails, or when
# there is no test at all.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${SSS_BUILD_DIR:-build}
jobs=$(nproc)

bash data/fetch.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DSSS_BUILD_TESTS=ON
cmake --build "$build" -j "$jobs"
ctest --test-dir "$build" --output-on-failure --no-tests=error -j "$jobs"
