#!/usr/bin/env bash
# The outputs a refactor must keep byte-identical, hashed: the default pipeline's pictures and
# baked meshes (tools/run-pipeline.sh, Table 1's timings aside), a sample bake of every method and
# of every optional stage (PLY and GLB), and sss-irrmap on the 8 sample environments.
#
#   tests/bench/output_hashes.sh BUILD_DIR OUT_DIR > hashes.txt
#
# Prints "sha256  path" per output, paths relative to OUT_DIR; diff two such lists made before
# and after a change. JSON reports and Table 1 hold timings and are left out; a GLB is hashed
# without the timings its embedded report holds, an EXR without its write time. Needs a
# Release build and data/fetch.sh's sample data.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

build=$(realpath "$1")
out=$(realpath -m "$2")
bin=$build/tools
meshes=data/cache/meshes
envs=data/cache/env
rm -rf "$out"
mkdir -p "$out"/{pipeline,bakes,irrmap}

# The default pipeline, its out/ folder moved into OUT_DIR/pipeline. SSS_TABLE=1: Table 1's bakes
# (the dragon at four resolutions, the teapot, the bunny) are outputs too; one timed frame each.
log=$out/log.txt
SSS_BUILD_DIR=$build SSS_WORK_DIR=$out/pipeline/paper-work SSS_TABLE=1 SSS_TABLE_FRAMES=1 \
  bash tools/run-pipeline.sh >"$log" 2>&1
cp -r out/. "$out/pipeline/"

# bake NAME ARGS...: the 50 mm bunny under forest.exr, one method or stage.
bake() {
  local name=$1
  shift
  "$bin/sss-bake" $meshes/bunny.ply -e $envs/forest.exr --size-mm 50 --quiet --threads 2 "$@" \
    -o "$out/bakes/$name" >>"$log" 2>&1
}
for method in exact gauss incremental hierarchical; do
  bake "method_$method.ply" -m marble --method "$method" --visibility none
done
bake method_pathtrace.ply -m marble --method pathtrace --walks 16 --visibility none
bake defaults_marble.ply -m marble
bake defaults_marble.glb -m marble
bake skim_bounces.ply -m skimmilk --bounces auto
bake ketchup_far_field.ply -m ketchup --far-field on --unscattered on --samples 32
bake skin_diffuse_entry.ply -m skin1 --entry diffuse --profile burley --energy halfspace
bake marble_beam_bounces.ply -m marble --bounces 2 --profile beam
"$bin/sss-bake" $meshes/teapot.ply --sky --size-mm 80 -m apple --quiet --threads 2 \
  -o "$out/bakes/teapot_sky.glb" >>"$log" 2>&1

for map in "$envs"/*.exr; do
  stem=$(basename "$map" .exr)
  "$bin/sss-irrmap" "$map" --radiance "$out/irrmap/${stem}_radiance.exr" \
    -o "$out/irrmap/${stem}_irradiance.exr" --quiet >>"$log" 2>&1
done

# A GLB embeds the bake's report, whose timings differ run to run: its JSON chunk is hashed
# with every timing ("seconds", "*_s") and the output path left out, beside its binary chunk.
hash_glb() {
  python3 - "$1" <<'PY'
import hashlib, json, struct, sys
data = open(sys.argv[1], "rb").read()
def untimed(node):
    if isinstance(node, dict):
        return {k: untimed(v) for k, v in node.items() if k not in ("seconds", "output") and not k.endswith("_s")}
    return [untimed(v) for v in node] if isinstance(node, list) else node
digest, offset = hashlib.sha256(), 12
while offset < len(data):
    length, kind = struct.unpack_from("<II", data, offset)
    chunk = data[offset + 8:offset + 8 + length]
    if kind == 0x4E4F534A:  # JSON
        chunk = json.dumps(untimed(json.loads(chunk)), sort_keys=True).encode()
    digest.update(chunk)
    offset += 8 + length
print(f"{digest.hexdigest()}  {sys.argv[1]}")
PY
}
# An EXR header holds the time it was written (capDate): hashed without that attribute.
hash_exr() {
  python3 - "$1" <<'PY'
import hashlib, sys
data = open(sys.argv[1], "rb").read()
digest, offset = hashlib.sha256(data[:8]), 8
while data[offset] != 0:  # attributes: name\0 type\0 size value, up to an empty name
    name_end = data.index(b"\0", offset)
    type_end = data.index(b"\0", name_end + 1)
    size = int.from_bytes(data[type_end + 1:type_end + 5], "little")
    end = type_end + 5 + size
    if data[offset:name_end] != b"capDate":
        digest.update(data[offset:end])
    offset = end
digest.update(data[offset:])
print(f"{digest.hexdigest()}  {sys.argv[1]}")
PY
}
cd "$out"
for exr in $(find . -type f -name '*.exr' | sort); do hash_exr "$exr"; done
find . -type f \( -name '*.ply' -o -name '*.png' \) \
  ! -name 'table1*' ! -name '*-frames.png' | sort | xargs sha256sum
for glb in $(find . -type f -name '*.glb' | sort); do hash_glb "$glb"; done
