#!/usr/bin/env python3
"""Writes poncho.obj, the garment of apps/scenes/poncho_dance.json.

A flat square poncho of side 2 A = 1.1 m in the x-z plane (y = 0) with a round neck hole of radius
R = 0.14 m at its centre, meshed by rays: NT sectors around the hole, each ray from the hole's
circle to the square's edge cut into NR rings (NT divisible by 4 puts a ray on every corner). Each
quad is split along alternating diagonals. Its `vt` is the pattern, the flat shape in metres (one
per vertex), and its triangles are split into two panels by the line z = 0, `front` (z > 0, the way the dancer faces) and
`back`, which the outputs carry back.
Run: python3 make_poncho.py > poncho.obj
"""
import math

A, R, NT, NR = 0.55, 0.14, 128, 18

points = []
for i in range(NR + 1):
    s = i / NR
    for j in range(NT):
        t = 2 * math.pi * j / NT
        c, d = math.cos(t), math.sin(t)
        edge = A / max(abs(c), abs(d))  # the square's boundary along this ray
        r = (1 - s) * R + s * edge
        points.append((r * c, r * d))


def vid(i, j):
    return i * NT + j % NT


front, back = [], []
for i in range(NR):
    for j in range(NT):
        a, b, c, d = vid(i, j), vid(i, j + 1), vid(i + 1, j + 1), vid(i + 1, j)
        # Normals along +y (outwards once it drapes): (b - a) x (c - a) has y = r dt (r' - r) > 0.
        quads = [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
        for tri in quads:
            z = sum(points[k][1] for k in tri) / 3
            (front if z > 0 else back).append(tri)

print("# poncho.obj: written by make_poncho.py (apps/scenes/data); units: metres")
print("# %d vertices, %d triangles; vt = the flat pattern in metres" % (len(points), len(front) + len(back)))
for x, z in points:
    print("v %.6f 0 %.6f" % (x, z))
for x, z in points:
    print("vt %.6f %.6f" % (x, z))
for name, tris in (("front", front), ("back", back)):
    print("g %s" % name)
    for t in tris:
        print("f " + " ".join("%d/%d" % (k + 1, k + 1) for k in t))
