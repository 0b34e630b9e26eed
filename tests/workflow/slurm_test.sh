#!/usr/bin/env bash
# The workflow's Slurm profile (tools/workflow/profiles/slurm) on a real Slurm: a one-node cluster
# started here (munged, slurmctld and slurmd from Debian's munge and slurm-wlm, with their key,
# socket, ports, state and logs in a scratch folder; no cgroups, no accounting database), the
# sample manifest plus one row that shares a batch run through the profile, then:
#   - every job went through sbatch: Slurm's job completion log lists exactly the jobs the dry run
#     planned (one per rule, `all` excepted, which Snakemake runs itself), each COMPLETED with
#     exit code 0, and each output file is named in the log of the Slurm job that wrote it;
#   - the outputs equal a local run's with one job per row (batch=1, -j 4): bakes, renders and the
#     contact sheet byte for byte, the JSON reports and reports.csv but for timings and the
#     output folder;
#   - the profile's status command tells a finished job from one Slurm cancelled.
# Quick settings: no shadow rays, half-space energy, no far field or unscattered light, 5 %
# tolerance, 96x96 renders.
# Exits 77 (ctest: skipped) with the reason when Slurm or munge is not installed or the daemons
# do not start; SSS_REQUIRE_SLURM=1 makes that a failure. The daemons are stopped on any exit.
# Usage: slurm_test.sh SOURCE_DIR BINARY_DIR
set -euo pipefail
src=$1 bin=$2/tools
started=$SECONDS
skip() {
  echo "slurm_test: SKIP: $*"
  [[ ${SSS_REQUIRE_SLURM:-0} != 1 ]] || { echo "slurm_test: FAIL: SSS_REQUIRE_SLURM=1" >&2; exit 1; }
  exit 77
}
fail() { echo "slurm_test: FAIL: $*" >&2; exit 1; }

# The daemons live in /usr/sbin, which a user's PATH may lack.
PATH=$PATH:/usr/sbin:/sbin
for program in munged mungekey slurmctld slurmd sbatch scontrol sinfo squeue scancel; do
  command -v "$program" >/dev/null ||
    skip "$program not found: install slurm-wlm and munge (apt-get install --no-install-recommends slurm-wlm munge)"
done

# munged refuses a socket whose folders others cannot traverse: the scratch folder is 0755.
work=$(mktemp -d)
chmod 755 "$work"
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/log"
chmod 700 "$work/state" "$work/spool"
export SLURM_CONF=$work/slurm.conf

# Stops what this test started, in order: jobs (their slurmstepd would outlive slurmd), then the
# daemons by their pid files, then the scratch folder. Runs on any exit, signals included.
stop_pid() {
  local file=$1 pid
  [[ -s $file ]] || return 0
  pid=$(<"$file")
  kill "$pid" 2>/dev/null || return 0
  for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || return 0; sleep 0.1; done
  kill -9 "$pid" 2>/dev/null || true
}
cleanup() {
  local status=$?
  if [[ -s $work/slurmctld.pid ]] && kill -0 "$(<"$work/slurmctld.pid")" 2>/dev/null; then
    scancel --quiet --full --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 50); do [[ -z $(squeue -h 2>/dev/null) ]] && break; sleep 0.2; done
  fi
  stop_pid "$work/slurmd.pid"
  stop_pid "$work/slurmctld.pid"
  stop_pid "$work/munge/munged.pid"
  rm -rf "$work"
  exit "$status"
}
trap cleanup EXIT
trap 'exit 143' TERM INT HUP

# Shows a daemon's log and skips: the daemons could not start here.
cannot_start() {
  local what=$1 log=$2
  [[ -f $log ]] && tail -n 20 "$log" | sed 's/^/  /'
  skip "$what did not start (log above)"
}

# munge, with its own key and socket.
mungekey --create --keyfile="$work/munge/munge.key" 2>/dev/null ||
  { head -c 1024 /dev/urandom >"$work/munge/munge.key" && chmod 600 "$work/munge/munge.key"; }
munged --socket="$work/munge/socket" --key-file="$work/munge/munge.key" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/seed" \
  --log-file="$work/munge/munged.log" || cannot_start munged "$work/munge/munged.log"

# Two free TCP ports for slurmctld and slurmd (another Slurm may hold the default 6817 and 6818).
read -r ctld_port node_port < <(python3 -c '
import socket
sockets = [socket.socket() for _ in range(2)]
for s in sockets:
    s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in sockets))')

# One node on localhost with 4 CPUs (two tool jobs of 2 threads at once, as the local run's -j 4)
# and 4000 MB (the profile asks 2000 per job) whatever this machine has (config_overrides); processes tracked by /proc
# (linuxproc) and no task plugin, so no cgroups; the job completion log instead of accounting.
user=$(id -un)
cat >"$SLURM_CONF" <<EOF
ClusterName=ssstest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$node_port
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$work/munge/socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$work/log/jobcomp.log
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmdParameters=config_overrides
ReturnToService=2
NodeName=ssstestnode NodeHostname=localhost NodeAddr=127.0.0.1 CPUs=4 RealMemory=4000 State=UNKNOWN
PartitionName=ssstest Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -f "$SLURM_CONF" || cannot_start slurmctld "$work/log/slurmctld.log"
slurmd -f "$SLURM_CONF" -N ssstestnode || cannot_start slurmd "$work/log/slurmd.log"
state=
for _ in $(seq 150); do
  state=$(sinfo --noheader --nodes=ssstestnode --format=%T 2>/dev/null || true)
  [[ $state == idle ]] && break
  sleep 0.2
done
[[ $state == idle ]] || {
  tail -n 20 "$work/log/slurmd.log" | sed 's/^/  /'
  cannot_start "the node (state '${state:-none}' after 30 s)" "$work/log/slurmctld.log"
}
echo "slurm_test: one-node Slurm up in $((SECONDS - started)) s"

# The sample manifest with absolute paths (snakemake runs in scratch folders), and the teapot in
# marble under forest: it shares the bunny's bake batch (environment, rotation, material, units)
# and render batch, so that a batch of two rows runs under Slurm too.
{
  IFS= read -r header
  echo "$header"
  while IFS=, read -r mesh units material env rotation; do
    echo "$src/$mesh,$units,$material,$src/$env,$rotation"
  done
  echo "$src/data/cache/meshes/teapot.ply,size:120,marble,$src/data/cache/env/forest.exr,0"
} <"$src/tools/workflow/sample_manifest.csv" >"$work/manifest.csv"
for f in $(tail -n +2 "$work/manifest.csv" | cut -d, -f1,4 | tr , ' '); do
  [[ -f $f ]] || fail "missing sample data $f: run data/fetch.sh"
done

# CI=true: Snakemake 7 then polls its cluster jobs every second instead of every 10 s (its only
# effect, snakemake/executors/__init__.py).
# Usage: run FOLDER BATCH [SNAKEMAKE OPTIONS...]
run() {
  local folder=$1 batch=$2
  shift 2
  mkdir -p "$folder"
  CI=true snakemake -s "$src/tools/workflow/Snakefile" -d "$folder" \
    --config manifest="$work/manifest.csv" out="$folder/out" bin="$bin" batch="$batch" \
    bake_args="--visibility none --energy halfspace --far-field off --unscattered off --tolerance 0.05" \
    render_args="--size 96x96" "$@"
}

run "$work/local" 1 -j 4 >"$work/local.log" 2>&1 ||
  { cat "$work/local.log"; fail "the local run failed"; }

# The jobs the profile should submit, from the dry run's job table ("rule count ..." lines
# between the dashes and "total").
run "$work/slurm" 16 -n --profile "$src/tools/workflow/profiles/slurm" >"$work/plan.log" 2>&1 ||
  { cat "$work/plan.log"; fail "the dry run failed"; }
awk '/^job +count/ {table = 1; next} table && $1 == "total" {exit}
     table && $1 ~ /^[a-z]/ && $1 != "all" {for (i = 0; i < $2; i++) print "sss-" $1}' \
  "$work/plan.log" | sort >"$work/planned"
bakes=$(grep -c '^sss-bake_' "$work/planned" || true)
renders=$(grep -c '^sss-render_' "$work/planned" || true)
[[ $bakes == 3 && $renders == 3 ]] ||
  fail "planned $bakes bake and $renders render jobs for 4 rows, expected 3 and 3 (one batch of two)"

run "$work/slurm" 16 --profile "$src/tools/workflow/profiles/slurm" >"$work/slurm.log" 2>&1 ||
  { tail -n 40 "$work/slurm.log"; fail "the run through Slurm failed"; }
echo "slurm_test: workflow through Slurm in $((SECONDS - started)) s"

# Every planned job ran as one Slurm job, completed, exit code 0; and no other job ran.
sed -E 's/.* Name=([^ ]*) JobState=([^ ]*) .* ExitCode=([^ ]*).*/\1 \2 \3/' "$work/log/jobcomp.log" \
  >"$work/jobs"
awk '{print $1}' "$work/jobs" | sort >"$work/ran"
diff -u "$work/planned" "$work/ran" >&2 || fail "the Slurm jobs (+) differ from the plan (-)"
awk '$2 != "COMPLETED" || $3 != "0:0"' "$work/jobs" | grep . >&2 && fail "Slurm jobs did not complete"
submitted=$(grep -c "^Submitted job .* with external jobid" "$work/slurm.log" || true)
[[ $submitted == $(wc -l <"$work/planned") ]] ||
  fail "Snakemake submitted $submitted jobs, planned $(wc -l <"$work/planned")"
# Each output was written inside a Slurm job: its job log (logs/slurm/RULE-JOBID.out, the
# Snakemake that ran the rule on the node) names it among the rule's outputs.
cat "$work"/slurm/logs/slurm/*.out >"$work/job_logs"
for f in "$work"/slurm/out/{env,bake,render}/*.* "$work/slurm/out/reports.csv" \
  "$work/slurm/out/contact_sheet.png"; do
  grep -qF -- "$f" "$work/job_logs" || fail "$(basename "$f") is named in no Slurm job's log"
done

# The same outputs as the local run: bakes and renders byte for byte (each is deterministic); the
# cubemaps and the contact sheet pixel for pixel (their headers hold the time and the command
# line); the reports but for timings and the folder they were written to.
(cd "$work/local/out" && find . -type f ! -path './bake/meshes/*' | sort) >"$work/local_files"
(cd "$work/slurm/out" && find . -type f ! -path './bake/meshes/*' | sort) >"$work/slurm_files"
diff -u "$work/local_files" "$work/slurm_files" >&2 || fail "the runs wrote different files"
while read -r f; do
  case $f in
    *.json | *.csv) ;;
    *.exr | ./contact_sheet.png)
      idiff -fail 0 -warn 0 "$work/local/out/$f" "$work/slurm/out/$f" >/dev/null ||
        fail "$f differs from the local run's" ;;
    *) cmp -s "$work/local/out/$f" "$work/slurm/out/$f" || fail "$f differs from the local run's" ;;
  esac
done <"$work/local_files"
python3 - "$work/local/out" "$work/slurm/out" "$work/local_files" <<'PY' ||
import csv, json, sys

local, slurm, files = sys.argv[1:4]

def timing(key):
    """The tools' timings: stages.total_s, energy.seconds, times_ms.gl_context, timings_ms.cpu."""
    parts = key.split(".")
    last = parts[-1]
    return last == "seconds" or last.endswith("_s") or bool({"times_ms", "timings_ms"} & set(parts))

def flat(value, prefix=""):
    if isinstance(value, dict):
        for key, item in value.items():
            yield from flat(item, f"{prefix}.{key}" if prefix else key)
    else:
        yield prefix, value

def kept(pairs, folder):
    return {k: (v.replace(folder, "OUT") if isinstance(v, str) else v)
            for k, v in pairs if not timing(k)}

def records(path, folder):
    """A JSON report as one record, a CSV as one per line, timings left out."""
    if path.endswith(".json"):
        return [kept(flat(json.load(open(path))), folder)]
    return [kept(row.items(), folder) for row in csv.DictReader(open(path))]

bad = 0
for name in (line.strip()[2:] for line in open(files)):
    if not name.endswith((".json", ".csv")):
        continue
    x, y = records(f"{local}/{name}", local), records(f"{slurm}/{name}", slurm)
    if x != y:
        bad += 1
        keys = sorted({k for a, b in zip(x, y) for k in a.keys() | b.keys() if a.get(k) != b.get(k)})
        print(f"{name}: differs from the local run's in {keys[:8]} ({len(x)} vs {len(y)} records)",
              file=sys.stderr)
sys.exit(1 if bad else 0)
PY
  fail "reports differ from the local run's"

# The status command: a finished job is a success, one that Slurm cancelled is a failure (the
# state a job killed at its time limit also maps to), one still queued is running.
status=$src/tools/workflow/profiles/slurm/status.py
first=$(sed -n 's/^Submitted job .* with external jobid .\([0-9]*\).*/\1/p' "$work/slurm.log" | head -1)
[[ $($status "$first") == success ]] || fail "status.py does not report job $first as a success"
held=$(sbatch --parsable --hold --output=/dev/null --wrap "sleep 60")
[[ $($status "$held") == running ]] || fail "status.py does not report held job $held as running"
scancel "$held"
[[ $($status "$held") == failed ]] || fail "status.py does not report cancelled job $held as failed"

echo "slurm_test: ok ($(wc -l <"$work/planned") Slurm jobs, $((SECONDS - started)) s)"
