#!/usr/bin/env python3
"""Writes notched_slab.mesh (MEDIT), the tet mesh of apps/scenes/plate_tear.json.

A slab of 12 x 7 x 2 cubic cells of side 0.01 m (0.12 x 0.07 x 0.02 m), each cell split into 6
tets around its (0,0,0)-(1,1,1) diagonal (conforming), with a notch: the cells of row j = 3
(0.03 < y < 0.04) with i < 4 (x < 0.04) are left out, a slot from the left side whose tip is at
x = 0.04. Pulled along y, the slab tears from the tip along y ~ 0.035.
Run: python3 make_notched_slab.py > notched_slab.mesh
"""
import itertools

NX, NY, NZ, H = 12, 7, 2, 0.01


def keep(i, j, k):
    return not (j == 3 and i < 4)


ids, nodes, tets = {}, [], []


def node(i, j, k):
    if (i, j, k) not in ids:
        ids[(i, j, k)] = len(nodes)
        nodes.append((i * H, j * H, k * H))
    return ids[(i, j, k)]


def det(a, b, c):
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])


for k, j, i in itertools.product(range(NZ), range(NY), range(NX)):
    if not keep(i, j, k):
        continue
    for p in itertools.permutations(range(3)):
        c = [0, 0, 0]
        t = [node(i, j, k)]
        for s in range(3):
            c[p[s]] = 1
            t.append(node(i + c[0], j + c[1], k + c[2]))
        x = [nodes[v] for v in t]
        d = [[x[s][a] - x[0][a] for a in range(3)] for s in range(1, 4)]
        if det(*d) < 0:
            t[1], t[2] = t[2], t[1]
        tets.append(t)

print("MeshVersionFormatted 1\nDimension 3\nVertices\n%d" % len(nodes))
for x in nodes:
    print("%.6g %.6g %.6g 0" % x)
print("Tetrahedra\n%d" % len(tets))
for t in tets:
    print("%d %d %d %d 0" % tuple(v + 1 for v in t))
print("End")
