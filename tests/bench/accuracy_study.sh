#!/usr/bin/env bash
# Runs the accuracy study and draws its charts into tests/bench/results/accuracy/.
#   tests/bench/accuracy_study.sh [BUILD_DIR] [extra accuracy_study arguments, e.g. --quick]
# Needs the sample data (data/fetch.sh) and gnuplot. Takes ~10 minutes on 2 cores.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
shift || true
out=$root/tests/bench/results/accuracy
mkdir -p "$out"
"$build/tests/bench/accuracy_study" "$out" "$@"
bash "$root/tests/bench/accuracy_charts.sh" "$out"
