#!/usr/bin/env python3
"""The pile's pedestal mesh as demsa writes it (orchestrator/experiments/geometry.cpp, pedestal_mesh), for benches
that run one case with another pedestal: a closed-top cylinder on z = 0, the top triangulated ring by ring (rings
TOP_ELEMENT apart, points TOP_ELEMENT apart along them), the rim and the side band with edges of RIM_ELEMENT.
With RIM_ELEMENT = 0.005, TOP_ELEMENT = 0.0125 it is byte-identical to the pedestal.stl demsa writes; with 0.005 /
0.005 to the one it wrote until 2026-12-04 (compact 5 mm triangles everywhere; docs/explanation/benchmarks.md, "The pedestal mesh").

Usage: bench/pedestal_stl.py RADIUS HEIGHT RIM_ELEMENT TOP_ELEMENT OUT.stl   (metres)
"""
import math
import sys

if len(sys.argv) != 6:
    sys.exit(__doc__)
R, H, rim, top_e = map(float, sys.argv[1:5])
out = sys.argv[5]
two_pi = 2.0 * math.pi
ring_count = max(1, round(R / top_e))
rings = [[(0.0, 0.0)]]
for k in range(1, ring_count + 1):
    r = R * k / ring_count
    e = rim if k == ring_count else top_e
    n = max(6, round(two_pi * r / e))
    rings.append([(r * math.cos(two_pi * i / n), r * math.sin(two_pi * i / n)) for i in range(n)])
tris = []
def top(p):
    return (p[0], p[1], H)
for k in range(1, len(rings)):
    a, b = rings[k - 1], rings[k]
    na, nb = len(a), len(b)
    if na == 1:
        tris += [(top(a[0]), top(b[j]), top(b[(j + 1) % nb])) for j in range(nb)]
        continue
    i = j = 0
    while i < na or j < nb:
        ta, tb = (i + 1) / na, (j + 1) / nb
        if j < nb and (i >= na or tb <= ta):
            tris.append((top(a[i % na]), top(b[j % nb]), top(b[(j + 1) % nb])))
            j += 1
        else:
            tris.append((top(a[i % na]), top(b[j % nb]), top(a[(i + 1) % na])))
            i += 1
outer = rings[-1]
bands = max(1, round(H / rim))
for i in range(len(outer)):
    p, q = outer[i], outer[(i + 1) % len(outer)]
    for k in range(bands):
        z0, z1 = H * k / bands, H * (k + 1) / bands
        tris.append(((p[0], p[1], z0), (q[0], q[1], z0), (q[0], q[1], z1)))
        tris.append(((p[0], p[1], z0), (q[0], q[1], z1), (p[0], p[1], z1)))
with open(out, "w") as f:
    f.write("solid pedestal\n")
    for t in tris:
        u = [t[1][c] - t[0][c] for c in range(3)]
        v = [t[2][c] - t[0][c] for c in range(3)]
        nrm = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        length = math.sqrt(sum(x * x for x in nrm))
        nrm = [x / length + 0.0 for x in nrm]
        f.write(" facet normal %.6e %.6e %.6e\n  outer loop\n" % tuple(nrm))
        for p in t:
            f.write("   vertex %.9e %.9e %.9e\n" % tuple(x + 0.0 for x in p))
        f.write("  endloop\n endfacet\n")
    f.write("endsolid pedestal\n")
