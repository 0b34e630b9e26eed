"""A sky brighter upwards and bluer, 256 x 128, as an uncompressed Radiance HDR: nowhere 20 times
its mean, so no compact light (envmap/compact_lights.h). The relight benchmarks' smooth sky.
    python3 tests/bench/smooth_sky.py OUT.hdr
"""
import math
import sys

w, h = 256, 128
out = bytearray(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (h, w))
for y in range(h):
    up = 0.5 + 0.5 * math.cos(math.pi * (y + 0.5) / h)
    rgb = (0.3 + up, 0.35 + up, 0.4 + 1.2 * up)
    m, e = math.frexp(max(rgb))
    out += bytes([int(c * 256.0 / 2.0 ** e) for c in rgb] + [e + 128]) * w
open(sys.argv[1], "wb").write(out)
