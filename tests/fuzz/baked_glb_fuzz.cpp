// libFuzzer target: readBakedGlb: the GLB header and chunk lengths, the glTF JSON (accessors,
// bufferViews, extras.sss) and every declared offset and count against the BIN chunk, the mesh.
#include "fuzz_main.h"

SSS_FUZZ_TARGET("baked_glb")
