// libFuzzer target: readImage on Radiance HDR bytes (lib/image's own reader, image_format.h).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("hdr")
