// libFuzzer target: the OFF header check and OpenMesh's OFF reader (ascii and binary) through
// loadMesh.
#include "fuzz_main.h"

SSS_FUZZ_TARGET("off")
