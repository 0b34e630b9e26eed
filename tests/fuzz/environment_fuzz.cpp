// libFuzzer target: readImage and loadEnvironment on EXR, HDR and PFM bytes (OpenImageIO reads
// files).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("environment")
