#!/bin/sh
# The tools' start-up: whole-process `--version` and `--help` of each tool, medians of RUNS runs
# (default 20), wall clock and the child's CPU time (getrusage), beside an empty process
# (/bin/true: the machine's own floor under its current load) and the shared libraries each tool
# loads (ldd). With BASELINE_DIR (a folder holding another build's three tools) both builds run
# alternately in one loop, so that they see the same load.
#   tests/bench/startup.sh BUILD_DIR [BASELINE_DIR] [RUNS] > startup.csv
set -eu
build=${1:?usage: startup.sh BUILD_DIR [BASELINE_DIR] [RUNS]}
baseline=${2:-}
runs=${3:-20}
python3 - "$build/tools" "$baseline" "$runs" <<'PY'
import os, resource, statistics, subprocess, sys, time
tools, baseline, runs = sys.argv[1], sys.argv[2], int(sys.argv[3])
dirs = {"after": tools}
if baseline:
    dirs["before"] = baseline
def timed(cmd):
    b = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - t
    a = resource.getrusage(resource.RUSAGE_CHILDREN)
    return 1e3 * wall, 1e3 * (a.ru_utime - b.ru_utime + a.ru_stime - b.ru_stime)
cases = [(t, f) for t in ("sss-irrmap", "sss-bake", "sss-render", "sss-relight") for f in ("--version", "--help")]
samples = {}
for _ in range(runs):
    for tool, flag in cases:
        for which, d in dirs.items():
            for key, value in zip(("wall", "cpu"), timed([f"{d}/{tool}", flag])):
                samples.setdefault((tool, flag, which, key), []).append(value)
    for key, value in zip(("wall", "cpu"), timed(["/bin/true"])):
        samples.setdefault(("true", "", "after", key), []).append(value)
def libraries(path):
    out = subprocess.run(["ldd", path], capture_output=True, text=True).stdout
    return sum(1 for line in out.splitlines() if "=>" in line or line.strip().startswith("/"))
print("tool,flag,wall_ms,cpu_ms,libraries,before_wall_ms,before_cpu_ms,before_libraries,load")
load = "%.1f" % os.getloadavg()[0]
for tool, flag in cases + [("true", "")]:
    med = lambda which, key: "%.1f" % statistics.median(samples[(tool, flag, which, key)]) \
        if (tool, flag, which, key) in samples else ""
    path = "/bin/true" if tool == "true" else f"{tools}/{tool}"
    before = "" if tool == "true" or not baseline else str(libraries(f"{baseline}/{tool}"))
    print(",".join([tool, flag, med("after", "wall"), med("after", "cpu"), str(libraries(path)),
                    med("before", "wall"), med("before", "cpu"), before, load]))
PY
