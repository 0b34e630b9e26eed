#!/usr/bin/env python3
"""How far two baked PLYs' radiance along the normal differ (radiance_normal_r/g/b, the vertices in
the same order): prints the relative RMS over all vertices and channels, against the second
file, and the largest relative difference of one value.
  ply_radiance_change.py A.ply B.ply"""
import math, struct, sys
SIZES = {"float": "f", "uchar": "B", "char": "b", "short": "h", "ushort": "H", "int": "i",
         "uint": "I", "double": "d"}
def radiance(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    fmt, names, count, in_vertex = "<", [], 0, False
    for line in data[:end].decode().splitlines():
        w = line.split()
        if w[:2] == ["element", "vertex"]: count, in_vertex = int(w[2]), True
        elif w[:1] == ["element"]: in_vertex = False
        elif w[:1] == ["property"] and in_vertex: fmt += SIZES[w[1]]; names.append(w[2])
    record = struct.Struct(fmt)
    idx = [names.index("radiance_normal_" + c) for c in "rgb"]
    return [[v[i] for i in idx] for v in record.iter_unpack(data[end:end + count * record.size])]
a, b = radiance(sys.argv[1]), radiance(sys.argv[2])
err2 = ref2 = worst = 0.0
for x, y in zip(a, b):
    for p, q in zip(x, y):
        err2 += (p - q) ** 2; ref2 += q * q
        if q > 0: worst = max(worst, abs(p - q) / q)
print(f"{math.sqrt(err2 / ref2):.3g} {worst:.3g}")
