#!/usr/bin/env bash
# Command 2: install the missing Debian packages the tests need (tools/install-deps.sh --tests),
# fetch the sample data (cached), then run the test suites that SSS_TEST_SUITES names (default: all
# three; each build is only redone when needed):
#   release   build Release into build/ (SSS_BUILD_DIR overrides) and run every test through ctest
#   sanitize  the same suite under ASan + UBSan in the checked build <build>-checked/ (clang;
#             tests/sanitizers/run.sh)
#   fuzz      every reader's fuzz target for SSS_FUZZ_SECONDS (default 15) each, in the same checked
#             build (tests/fuzz/run.sh)
# Exits non-zero when a step or a test fails, or when there is no test at all.
#   SSS_TEST_SUITES=release bash tools/test.sh   # the Release suite only
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${SSS_BUILD_DIR:-build}
jobs=$(nproc)
suites=${SSS_TEST_SUITES:-release sanitize fuzz}

for suite in $suites; do
  case $suite in
    release | sanitize | fuzz) ;;
    *)
      echo "test: error: unknown suite '$suite' in SSS_TEST_SUITES (release, sanitize, fuzz)" >&2
      exit 2
      ;;
  esac
done

bash tools/install-deps.sh --tests
bash data/fetch.sh --tests
for suite in $suites; do
  start=$SECONDS
  echo "test: suite $suite"
  case $suite in
    release)
      # Both on: command 1 (tools/setup.sh) leaves them off in the same build folder.
      cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DSSS_BUILD_TESTS=ON \
        -DSSS_BUILD_BENCHMARKS=ON
      cmake --build "$build" -j "$jobs"
      ctest --test-dir "$build" --output-on-failure --no-tests=error -j "$jobs"
      # ctest names a skipped test only; the test's own line says why (slurm_test without
      # slurm-wlm and munge, or where their daemons cannot start).
      grep -h ": SKIP: " "$build/Testing/Temporary/LastTest.log" || true
      ;;
    sanitize) bash tests/sanitizers/run.sh "$build-checked" ;;
    fuzz) bash tests/fuzz/run.sh "${SSS_FUZZ_SECONDS:-15}" "$build-checked" ;;
  esac
  echo "test: suite $suite passed in $((SECONDS - start)) s"
done
