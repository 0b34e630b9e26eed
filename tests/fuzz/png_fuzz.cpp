// libFuzzer target: readImage on PNG bytes (lib/image's own reader, image_format.h).
#include "fuzz_main.h"

SSS_FUZZ_TARGET("png")
