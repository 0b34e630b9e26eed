#!/usr/bin/env bash
# Peak memory of sss-bake against triangles: the four sample dragons (11K to 871K
# triangles) and two subdivided ones made by subdivide_mesh in a temporary folder (dragon x 2^2 =
# 3.5M, dragon_res2 x 7^2 = 9.9M triangles; never committed), each baked with
#   cheap:   --visibility none --energy halfspace  (the cubemap's E, no random walks)
#   default: --samples 16                           (Embree shadow rays, auto energy: escape walks)
# (marble, 150 mm, --sky, --threads 2), peak RSS by /usr/bin/time -v, against the estimate that
# sss-bake refuses a mesh by (read from its refusal under SSS_MEMORY_LIMIT_MB=1).
# Usage: tests/bench/memory_sweep.sh [BUILD_DIR] [--charts-only]
# Output: tests/bench/results/bake/memory.csv, memory.png. 6-9 minutes on 2 cores; 2 GB of memory
# and 250 MB of temporary files at most.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
out=$root/tests/bench/results/bake
meshes=$root/data/cache/meshes
mkdir -p "$out"
[[ -f $meshes/dragon.ply ]] || { echo "missing sample data: run data/fetch.sh" >&2; exit 1; }

if [[ ${2:-} != --charts-only ]]; then
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$build/tests/bench/subdivide_mesh" "$meshes/dragon.ply" "$tmp/dragon_x4.ply" 2 >&2
"$build/tests/bench/subdivide_mesh" "$meshes/dragon_res2.ply" "$tmp/dragon_res2_x49.ply" 7 >&2

csv=$out/memory.csv
echo "mesh,vertices,triangles,settings,peak_rss_mib,estimate_mib,wall_s,rss_bytes_per_triangle" \
  > "$csv"
for mesh in "$meshes"/dragon_res4.ply "$meshes"/dragon_res3.ply "$meshes"/dragon_res2.ply \
            "$meshes"/dragon.ply "$tmp"/dragon_x4.ply "$tmp"/dragon_res2_x49.ply; do
  for settings in cheap default; do
    case $settings in
      cheap) flags=(--visibility none --energy halfspace) ;;
      default) flags=(--samples 16) ;;
    esac
    name=$(basename "$mesh" .ply)
    echo "== $name $settings" >&2
    bake=("$build/tools/sss-bake" "$mesh" --sky -m marble --size-mm 150 --threads 2 "${flags[@]}")
    # The estimate: "<file>: baking N triangles needs about X GB, Y GB available".
    estimate=$({ SSS_MEMORY_LIMIT_MB=1 "${bake[@]}" -q -o "$tmp/out.ply" 2>&1 || true; } |
               sed -n 's/.*needs about \([0-9.e+]*\) GB.*/\1/p')
    [[ -n $estimate ]] || { echo "sss-bake under SSS_MEMORY_LIMIT_MB=1: no estimate" >&2; exit 1; }
    /usr/bin/time -v "${bake[@]}" -o "$tmp/out.ply" --json "$tmp/out.json" 2> "$tmp/time.txt"
    rss_kb=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$tmp/time.txt")
    wall=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$tmp/time.txt" |
           awk -F: '{ s = 0; for (i = 1; i <= NF; i++) s = 60 * s + $i; print s }')
    read -r vertices triangles < <(python3 -c 'import json,sys; r=json.load(open(sys.argv[1]))
m=r["mesh"]; print(m["vertices"], m["triangles"])' "$tmp/out.json")
    awk -v n="$name" -v v="$vertices" -v t="$triangles" -v s="$settings" -v k="$rss_kb" \
        -v e="$estimate" -v w="$wall" 'BEGIN { printf "%s,%d,%d,%s,%.1f,%.1f,%.2f,%.0f\n",
        n, v, t, s, k / 1024, e * 1e9 / 1048576, w, k * 1024 / t }' | tee -a "$csv"
  done
done
fi

gnuplot <<GNUPLOT
set datafile separator ","
set terminal pngcairo size 900,600 noenhanced
set output "$out/memory.png"
set title "sss-bake peak memory vs triangles (dragons, marble, 150 mm, --sky, 2 threads)"
set logscale xy
set xrange [5000:2e7]
set xlabel "triangles"
set ylabel "peak RSS (MiB)"
set key left top
set grid
plot "< grep ',default,' '$out/memory.csv'" using 3:5 with linespoints pt 7 \\
       title "default (--samples 16: shadow rays, escape walks)", \\
     "< grep ',cheap,' '$out/memory.csv'" using 3:5 with linespoints pt 5 \\
       title "--visibility none --energy halfspace", \\
     "< grep ',default,' '$out/memory.csv'" using 3:6 with lines dt 2 lw 2 \\
       title "estimate sss-bake refuses by (150 MB + 256 B per triangle)"
GNUPLOT
echo "wrote $out/memory.csv, memory.png" >&2
