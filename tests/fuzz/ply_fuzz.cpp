// libFuzzer target: the strict PLY reader (lib/mesh/ply_format) through loadMesh and its cleanup.
#include "fuzz_main.h"

SSS_FUZZ_TARGET("ply")
