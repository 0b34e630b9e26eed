// libFuzzer target: loadMesh on a glTF 2.0 binary (.glb): the GLB header and chunk lengths, the
// JSON, buffers, bufferViews, accessors (strides, sparse, normalized), the node graph and its
// transforms, every primitive mode, the weld and the cleanup (mesh/gltf_reader.h).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("glb")
