# shellcheck shell=bash
# Sourced by the benchmark scripts: elapsed COMMAND... runs the command (its stdout discarded; it
# must succeed) and prints its wall time in seconds, to the millisecond.
elapsed() {
  python3 -c 'import subprocess,sys,time; t=time.perf_counter(); subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL); print(f"{time.perf_counter()-t:.3f}")' "$@"
}
