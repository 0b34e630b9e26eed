#!/usr/bin/env bash
# Command 2: fetch the sample data (cached), then run the test suites that SSS_TEST_SUITES names
# (default: release; each build is only redone when needed):
#   release   build Release into build/ (SSS_BUILD_DIR overrides) and run every test through ctest
#   sanitize  the same suite under ASan + UBSan in <build>-sanitize/ (tests/sanitizers/run.sh)
#   fuzz      every reader's fuzz target for SSS_FUZZ_SECONDS (default 30) in <build>-fuzz/
#             (tests/fuzz/run.sh; clang)
# Exits non-zero when a step or a test fails, or when there is no test at all.
#   SSS_TEST_SUITES="release sanitize fuzz" bash tools/test.sh   # all three
# CI runs the default: the sanitizer suite is not yet green on llvmpipe (Mesa's driver leaks under
# LeakSanitizer, tests/sanitizers/run.sh), and the three together take over 20 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build=${SSS_BUILD_DIR:-build}
jobs=$(nproc)
suites=${SSS_TEST_SUITES:-release}

for suite in $suites; do
  case $suite in
    release | sanitize | fuzz) ;;
    *)
      echo "test: error: unknown suite '$suite' in SSS_TEST_SUITES (release, sanitize, fuzz)" >&2
      exit 2
      ;;
  esac
done

bash data/fetch.sh
for suite in $suites; do
  start=$SECONDS
  echo "test: suite $suite"
  case $suite in
    release)
      cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DSSS_BUILD_TESTS=ON
      cmake --build "$build" -j "$jobs"
      ctest --test-dir "$build" --output-on-failure --no-tests=error -j "$jobs"
      ;;
    sanitize) bash tests/sanitizers/run.sh "$build-sanitize" ;;
    fuzz) bash tests/fuzz/run.sh "${SSS_FUZZ_SECONDS:-30}" "$build-fuzz" ;;
  esac
  echo "test: suite $suite passed in $((SECONDS - start)) s"
done
