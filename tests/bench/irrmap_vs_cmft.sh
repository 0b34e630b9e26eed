#!/bin/sh
# sss-irrmap against cmft (github.com/dariomanesku/cmft) on the eight sample maps,
# 1024x512 -> 32x32 irradiance faces, in one run:
#   tests/bench/irrmap_vs_cmft.sh BUILD_DIR [CMFT_BINARY] [RUNS] [TOLERANCE]
# BUILD_DIR: a Release build with benchmarks (irrmap_compare); CMFT_BINARY: cmft's cmft_cli
# (built apart from this repository; without it only our side is measured); RUNS (default 7)
# runs of each program per map, interleaved, medians reported; TOLERANCE (default 0.01) is
# sss-irrmap's --tolerance. cmft reads each map as an uncompressed RGBA32F DDS (its fastest input;
# written by irrmap_compare dds), we read the EXR (DWAB-compressed float) itself.
# Writes tests/bench/results/irradiance/vs_cmft.csv (per map: our in-process wall and CPU time
# from the tool's JSON report, also on the same pixels as an uncompressed EXR ("raw", the
# equivalent of cmft's uncompressed DDS), the whole process for both, the start-up floor = a whole
# `sss-irrmap --help`, the in-process time of sss-irrmap on a 64x32 map (a first read and write),
# and the error of both against the exact sum over every texel) and batch.csv (the eight maps in
# one process, irrmap_compare batch).
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:?usage: irrmap_vs_cmft.sh BUILD_DIR [CMFT_BINARY] [RUNS] [TOLERANCE]}
cmft=${2:-}
runs=${3:-7}
tolerance=${4:-0.01}
out="$root/tests/bench/results/irradiance"
irrmap="$build/tools/sss-irrmap"
compare=$(find "$build" -name irrmap_compare -type f | head -n 1)
[ -x "$irrmap" ] && [ -x "$compare" ] || { echo "build sss-irrmap and irrmap_compare first" >&2; exit 1; }
[ -z "$cmft" ] || [ -x "$cmft" ] || { echo "$cmft: not an executable" >&2; exit 1; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$compare" tiny "$work/tiny.exr"
maps=""
for f in "$root"/data/cache/env/*.exr; do
  m=$(basename "$f" .exr)
  maps="$maps $m"
  [ -z "$cmft" ] || "$compare" dds "$f" "$work/$m.dds" 2>/dev/null
  "$compare" exr "$f" "$work/${m}_raw.exr" 2>/dev/null
done

# Timing in Python: wall clock and the child's CPU time (getrusage) at microsecond resolution.
python3 - "$root" "$work" "$irrmap" "$cmft" "$runs" "$tolerance" $maps > "$work/times.csv" <<'PY'
import json, os, resource, statistics, subprocess, sys, time
root, work, irrmap, cmft, runs, tol, maps = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]), sys.argv[6], sys.argv[7:]
def timed(cmd):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return 1e3 * wall, 1e3 * cpu
keys = ("in", "in_cpu", "whole", "whole_cpu", "raw_in", "raw_in_cpu", "raw_whole", "cmft", "cmft_cpu", "startup_floor", "startup_floor_cpu", "tiny_in", "tiny_in_cpu")
samples = {m: {k: [] for k in keys} for m in maps}
for r in range(runs):
    for m in maps:
        s = samples[m]
        w, c = timed([irrmap, "--help"])
        s["startup_floor"].append(w); s["startup_floor_cpu"].append(c)
        timed([irrmap, f"{work}/tiny.exr", "-o", f"{work}/tiny_e.exr", "--size", "32", "--json", f"{work}/tiny.json", "-q"])
        report = json.load(open(f"{work}/tiny.json"))
        s["tiny_in"].append(report["timings_ms"]["total"]); s["tiny_in_cpu"].append(report["timings_ms"]["cpu"])
        w, c = timed([irrmap, f"{root}/data/cache/env/{m}.exr", "-o", f"{work}/{m}_ours.exr", "--size", "32",
                      "--tolerance", tol, "--json", f"{work}/{m}.json", "-q"])
        s["whole"].append(w); s["whole_cpu"].append(c)
        report = json.load(open(f"{work}/{m}.json"))
        s["in"].append(report["timings_ms"]["total"]); s["in_cpu"].append(report["timings_ms"]["cpu"])
        w, c = timed([irrmap, f"{work}/{m}_raw.exr", "-o", f"{work}/{m}_raw_ours.exr", "--size", "32",
                      "--tolerance", tol, "--json", f"{work}/{m}_raw.json", "-q"])
        s["raw_whole"].append(w)
        report = json.load(open(f"{work}/{m}_raw.json"))
        s["raw_in"].append(report["timings_ms"]["total"]); s["raw_in_cpu"].append(report["timings_ms"]["cpu"])
        if cmft:
            w, c = timed([cmft, "--input", f"{work}/{m}.dds", "--filter", "irradiance", "--dstFaceSize", "32",
                          "--outputNum", "1", "--output0", f"{work}/{m}_cmft", "--output0params", "dds,rgba32f,cubemap",
                          "--silent"])
            s["cmft"].append(w); s["cmft_cpu"].append(c)
med = lambda v: statistics.median(v) if v else float("nan")
for m in maps:
    s = samples[m]
    report = json.load(open(f"{work}/{m}.json"))
    print(",".join([m] + ["%.2f" % med(s[k]) for k in keys]
                   + [report["method"], "%.6g" % report["estimated_error"]]))
PY

header="map,ours_in_process_ms,ours_in_process_cpu_ms,ours_whole_ms,ours_whole_cpu_ms,ours_raw_in_process_ms,ours_raw_in_process_cpu_ms,ours_raw_whole_ms,cmft_whole_ms,cmft_whole_cpu_ms,startup_floor_ms,startup_floor_cpu_ms,tiny_in_process_ms,tiny_in_process_cpu_ms,ours_method,ours_estimated_error,ratio_in_process_to_cmft,ratio_raw_in_process_to_cmft,ratio_cpu_in_process_to_cmft_cpu,ratio_whole_to_cmft,ours_rms,ours_worst_texel,ours_probe_rms,cmft_rms,cmft_worst_texel,cmft_min_texel,cmft_probe_rms"
echo "$header" > "$out/vs_cmft.csv"
while IFS=, read -r m rest; do
  line="$m,$rest"
  if [ -n "$cmft" ]; then
    errors=$("$compare" error "$root/data/cache/env/$m.exr" "$work/${m}_ours.exr" "$work/${m}_cmft.dds" 2>/dev/null)
    ours=$(echo "$errors" | awk -F, '$1 == "sss-irrmap" { print $2 "," $3 "," $5 }')
    theirs=$(echo "$errors" | awk -F, '$1 == "cmft" { print $2 "," $3 "," $4 "," $5 }')
    ratio=$(echo "$rest" | awk -F, '{ printf "%.3f,%.3f,%.3f,%.3f", $1 / $8, $5 / $8, $2 / $9, $3 / $8 }')
    line="$line,$ratio,$ours,$theirs"
  fi
  echo "$line" >> "$out/vs_cmft.csv"
done < "$work/times.csv"

"$compare" batch "$work" "$root"/data/cache/env/*.exr > "$out/batch.csv" 2>/dev/null
echo "wrote $out/vs_cmft.csv $out/batch.csv"
