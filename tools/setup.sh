#!/usr/bin/env bash
# Command 1: install the missing Debian packages, fetch the sample data, build Release into build/
# (SSS_BUILD_DIR overrides) and run the default pipeline, which writes its pictures to out/.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${SSS_BUILD_DIR:-build}

bash tools/install-deps.sh
bash data/fetch.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" -j "$(nproc)"
SSS_BUILD_DIR=$build bash tools/run-pipeline.sh
