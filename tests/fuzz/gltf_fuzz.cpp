// libFuzzer target: loadMesh on a glTF 2.0 text asset (.gltf): base64 data: URIs and external URIs,
// the JSON, buffers, bufferViews, accessors (strides, sparse, normalized), the node graph and its
// transforms, every primitive mode, the weld and the cleanup (mesh/gltf_reader.h).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("gltf")
