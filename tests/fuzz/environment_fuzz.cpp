// libFuzzer target: readImage and loadEnvironment on EXR, HDR and PFM bytes (lib/image reads
// files).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("environment")
