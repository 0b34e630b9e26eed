#!/usr/bin/env python3
"""Snakemake's cluster-status command for Slurm: prints `running`, `success` or `failed` for the
job id that `sbatch --parsable` printed (JOBID or JOBID;CLUSTER).

Without it, Snakemake learns a job's end only from a marker file that the job's own script
writes as it finishes; a job that Slurm ends (time limit, memory, node failure, scancel) writes
none, and Snakemake would wait for it forever. The state comes from slurmctld (`scontrol show
job`, which knows a job until MinJobAge, 300 s by default, after it ends), else from the
accounting (`sacct`, where the site keeps it). A job neither knows is reported failed: Snakemake
then reruns it (restart-times) or stops, rather than wait for ever."""
import re
import subprocess
import sys
import time

# Slurm job states (squeue(1), "JOB STATE CODES") that mean the job may still finish.
RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED",
           "REQUEUE_FED", "REQUEUE_HOLD", "RESIZING", "SIGNALING", "STAGE_OUT", "STOPPED",
           "RESV_DEL_HOLD", "SPECIAL_EXIT"}


def run(command):
    """The command's output, or None when it fails (slurmctld busy or restarting, job unknown)."""
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return done.stdout if done.returncode == 0 else None


def state(job):
    shown = run(["scontrol", "show", "job", "--oneliner", job])
    if shown:
        match = re.search(r"\bJobState=(\S+)", shown)
        if match:
            return match.group(1)
    # The job's allocation line only (-X), its state's first word ("CANCELLED by 0").
    accounted = run(["sacct", "--noheader", "--parsable2", "--allocations", "--format=State",
                     "--jobs", job])
    if accounted and accounted.split():
        return accounted.split()[0]
    return None


def main():
    job = sys.argv[1].split(";")[0]
    # slurmctld may be briefly unreachable (restart, overload): ask again before giving up.
    for attempt in range(3):
        found = state(job)
        if found:
            break
        time.sleep(2 * (attempt + 1))
    if found in RUNNING:
        print("running")
    elif found == "COMPLETED":
        print("success")
    else:
        print("failed")


if __name__ == "__main__":
    main()
