#!/usr/bin/env bash
# Fuzzes every reader: builds the libFuzzer targets of tests/fuzz in the checked build of
# tests/sanitizers/build.sh (clang, ASan + UBSan, coverage; the sanitizer suite shares it) in
# BUILD_DIR (default build-checked/) and runs each target for SECONDS_EACH seconds (default 60), as
# many at once as there are cores, starting from its committed seed corpus
# (tests/fuzz/corpus/<target>/) and what earlier runs in BUILD_DIR found
# (BUILD_DIR/fuzz/corpus/<target>/). Fails when any target crashes, leaks, exceeds the
# memory limits (a reader must refuse a huge declared size before allocating it) or spends more
# than the timeout on one input; the reproducer is saved under BUILD_DIR/fuzz/artifacts/<target>/
# (commit it to tests/fuzz/regressions/<target>/, fix the reader, and fuzz_regressions_test replays
# it in every build). The last line per target (runs, coverage) goes to BUILD_DIR/fuzz/summary.txt.
#   tests/fuzz/run.sh [SECONDS_EACH] [BUILD_DIR]       SSS_FUZZ_TARGETS="ply obj" for some only
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
seconds=${1:-60}
build=$(realpath -m "${2:-$root/build-checked}")
read -r -a targets <<<"${SSS_FUZZ_TARGETS:-ply obj off stl environment baked_ply baked_glb gltf glb exr hdr png material_map}"
jobs=$(nproc)
cd "$root"

bash tests/sanitizers/build.sh "$build" $(printf '%s_fuzz ' "${targets[@]}")

source tests/sanitizers/env.sh
# Over-allocation is a finding (the readers' size checks come first), not a std::bad_alloc.
export ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=0:strict_string_checks=1"
# What a reader may allocate once its memory check (core/memory.h) has passed: the glTF reader
# checks a scene's placed copies against it, under libFuzzer's -malloc_limit_mb below.
export SSS_MEMORY_LIMIT_MB=900
work="$build/fuzz"
mkdir -p "$work"
: >"$work/summary.txt"

# Runs one target; its output goes to work/<target>.log, its last stats line to the summary.
fuzz() {
  local t=$1 dict=()
  mkdir -p "$work/corpus/$t" "$work/artifacts/$t"
  [[ -f tests/fuzz/dict/$t.dict ]] && dict=(-dict="tests/fuzz/dict/$t.dict")
  [[ $t == baked_ply ]] && dict=(-dict=tests/fuzz/dict/ply.dict)
  [[ $t == exr || $t == hdr ]] && dict=(-dict=tests/fuzz/dict/environment.dict)
  [[ $t == glb ]] && dict=(-dict=tests/fuzz/dict/gltf.dict)
  local status=0
  "$build/tests/fuzz/${t}_fuzz" "$work/corpus/$t" "tests/fuzz/corpus/$t" "${dict[@]}" \
    -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -max_len=16384 -close_fd_mask=3 -print_final_stats=1 \
    -artifact_prefix="$work/artifacts/$t/" >"$work/$t.log" 2>&1 || status=$?
  local done runs
  done=$(sed -nE 's/^#[0-9]+[[:space:]]+DONE[[:space:]]+//p' "$work/$t.log" | tail -1)
  runs=$(sed -nE 's/^stat::number_of_executed_units: ([0-9]+)/\1/p' "$work/$t.log" | tail -1)
  if [[ $status -eq 0 ]]; then
    echo "$t: ok, ${runs:-?} runs in ${seconds} s, ${done:-no final stats}" >>"$work/summary.txt"
  else
    local found
    found=$(ls -t "$work/artifacts/$t/" | head -1 || true)
    echo "$t: FAILED (exit $status), reproducer: $work/artifacts/$t/${found:-?}, log: $work/$t.log" \
      >>"$work/summary.txt"
    grep -E 'ERROR|SUMMARY|WARNING: .*Sanitizer|==[0-9]+==|#[0-9]+ 0x' "$work/$t.log" | head -40 >&2 || true
  fi
  return "$status"
}

failed=0
running=0
for t in "${targets[@]}"; do
  if ((running >= jobs)); then
    wait -n || failed=1
    ((running--))
  fi
  echo "fuzz: $t for $seconds s"
  fuzz "$t" &
  ((++running))
done
while ((running > 0)); do
  wait -n || failed=1
  ((running--))
done
cat "$work/summary.txt"
if ((failed)); then
  echo "fuzz: error: a target failed; replay with $build/tests/fuzz/<target>_fuzz <reproducer>" >&2
  exit 1
fi
