// libFuzzer target: readBakedPly: the sss header comments, the per-vertex E and B channels, a
// relightable bake's transfer and key, the mesh.
#include "fuzz_main.h"

SSS_FUZZ_TARGET("baked_ply")
