// libFuzzer target: OpenMesh's OBJ reader through lib/mesh/openmesh_reader and loadMesh's cleanup.
#include "fuzz_main.h"

SSS_FUZZ_TARGET("obj")
