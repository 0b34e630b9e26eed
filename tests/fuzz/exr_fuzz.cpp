// libFuzzer target: readImage on OpenEXR bytes (lib/image's own reader, image_format.h).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("exr")
