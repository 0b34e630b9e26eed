#!/usr/bin/env bash
# Two builds of a Google Benchmark program measured in one run, alternating, so that a shared
# machine's drift falls on both alike: the before/after tables of a change
# (tests/bench/results/*/*_cost.csv).
#   tests/bench/bake_ab.sh BEFORE_BENCH AFTER_BENCH OUT.csv [RUNS] [BENCHMARKS]
# RUNS per side (default 5); BENCHMARKS space-separated names after SSS_AB_PREFIX (default
# "BM_BakeDragon/", bake_bench's; "" for diffusion_bench's "dragon_res3/gauss/0.01"), default
# "res2_auto res2_rays res2_none".
# Writes: benchmark, the medians, their ratio, each side's runs, and each side's rays per vertex
# (bake_bench's `samples` counter). Needs the sample data (data/fetch.sh); run from the root.
set -euo pipefail
before=$1 after=$2 out=$3 runs=${4:-5}
prefix=${SSS_AB_PREFIX-BM_BakeDragon/}
benchmarks=${5:-res2_auto res2_rays res2_none}

# Seconds and samples of one run of one benchmark: "SECONDS SAMPLES".
run_once() {
  "$1" --benchmark_filter="^$prefix$2/" --benchmark_format=csv 2>/dev/null |
    awk -F, '/^name,/ { for (i = 1; i <= NF; ++i) { gsub(/"/, "", $i); col[$i] = i }; next }
             /^"/ { s = col["samples"] ? $col["samples"] : "";
                                 print $col["real_time"], (s == "" ? "-" : s) }'
}

median() { tr ' ' '\n' | sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

tmp=$(mktemp "$out.XXXXXX")
trap 'rm -f "$tmp"' EXIT
echo "benchmark,before_median_s,after_median_s,after_over_before,before_runs_s,after_runs_s,before_samples,after_samples" >"$tmp"
for b in $benchmarks; do
  bt="" at="" bs="" as=""
  for ((i = 0; i < runs; ++i)); do
    read -r t s < <(run_once "$before" "$b")
    bt="$bt $t" bs=$s
    read -r t s < <(run_once "$after" "$b")
    at="$at $t" as=$s
    echo "bake_ab: $b run $((i + 1))/$runs" >&2
  done
  bm=$(echo $bt | median) am=$(echo $at | median)
  printf '%s,%.3f,%.3f,%.3f,%s,%s,%s,%s\n' "$b" "$bm" "$am" "$(awk -v a="$am" -v b="$bm" 'BEGIN { print a / b }')" \
    "$(echo $bt)" "$(echo $at)" "$bs" "$as" >>"$tmp"
done
mv "$tmp" "$out"
trap - EXIT
cat "$out"
