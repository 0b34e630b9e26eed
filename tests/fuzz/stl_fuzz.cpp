// libFuzzer target: the STL check and OpenMesh's STL reader (ascii and binary) through loadMesh.
#include "fuzz_main.h"

SSS_FUZZ_TARGET("stl")
