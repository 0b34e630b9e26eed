#!/usr/bin/env bash
# The relightable bake against fresh bakes (relight_study.cpp): with sss-bake's defaults, and with
# the stages traced per environment off in every bake (--traced-off: the stored transfer's own
# error). Writes tests/bench/results/relight/{defaults,traced_off}/relight.csv and
# relight_cost.csv (the second without dragon_res3). About an hour on 2 cores; --quick: the marble
# bunny, 2 HDRs, 2 suns.
#   bash tests/bench/relight_study.sh [BUILD_DIR] [--quick]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
build=${1:-build}
quick=${2:-}
bash data/fetch.sh >/dev/null
out=tests/bench/results/relight
"$build/tests/bench/relight_study" "$out/defaults" data/cache $quick
"$build/tests/bench/relight_study" "$out/traced_off" data/cache $quick --skip-large --traced-off
