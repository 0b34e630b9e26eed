// libFuzzer target: parseMaterialMap on a JSON material map (sss-bake --material-map MAP.json).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("material_map")
