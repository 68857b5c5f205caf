#!/usr/bin/python3
"""Writes the same surface with every edge longer than the median edge length split at its midpoint
(over passes until none is): check_fit.py's nearest-centroid search misjudges distances to long,
thin triangles (a CAD tessellation's fans), and measures the same surface with short ones exactly.

  split_long_edges.py INPUT OUTPUT.off [--length L]

Each triangle is cut by the pattern of its split edges (1: in two; 2: in three, across the shorter
diagonal; 3: in four), so the output is closed and manifold where the input is, and every output
triangle lies inside an input triangle.
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', 'shared', 'tools'))
from meshio import read_mesh, triangles  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('input')
    ap.add_argument('output')
    ap.add_argument('--length', type=float, help='split edges longer than this (default: the median)')
    a = ap.parse_args()
    if not a.output.lower().endswith('.off'):
        sys.exit('split_long_edges.py: %s: the output is written as OFF; name it .off' % a.output)
    v, f, _ = read_mesh(a.input)
    t, _ = triangles(f)
    points = [tuple(p) for p in v]
    tris = [tuple(int(i) for i in x) for x in t]
    edges = np.unique(np.sort(np.vstack([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1), axis=0)
    h = a.length if a.length else float(np.median(np.linalg.norm(v[edges[:, 0]] - v[edges[:, 1]], axis=1)))

    def length(p, q):
        return sum((points[p][k] - points[q][k]) ** 2 for k in range(3)) ** 0.5

    while True:
        mid = {}
        for x in tris:
            for i in range(3):
                p, q = x[i], x[(i + 1) % 3]
                key = (min(p, q), max(p, q))
                if key not in mid and length(p, q) > h:
                    mid[key] = len(points)
                    points.append(tuple((points[p][k] + points[q][k]) / 2 for k in range(3)))
        if not mid:
            break
        out = []
        for x in tris:
            m = [mid.get((min(x[i], x[(i + 1) % 3]), max(x[i], x[(i + 1) % 3]))) for i in range(3)]
            n = sum(e is not None for e in m)
            if n == 0:
                out.append(x)
                continue
            if n == 3:
                p0, p1, p2 = x
                m01, m12, m20 = m
                out += [(p0, m01, m20), (m01, p1, m12), (m20, m12, p2), (m01, m12, m20)]
                continue
            # Rotate so that edge 0 is split (n == 1), or edges 0 and 1 (n == 2).
            for r in range(3):
                xr, mr = x[r:] + x[:r], m[r:] + m[:r]
                if (n == 1 and mr[0] is not None) or (n == 2 and mr[0] is not None and mr[1] is not None):
                    break
            p0, p1, p2 = xr
            if n == 1:
                out += [(p0, mr[0], p2), (mr[0], p1, p2)]
            else:
                m01, m12 = mr[0], mr[1]
                out.append((m01, p1, m12))
                if length(p0, m12) < length(m01, p2):
                    out += [(p0, m01, m12), (p0, m12, p2)]
                else:
                    out += [(p0, m01, p2), (m01, m12, p2)]
        tris = out
    with open(a.output, 'w') as o:
        o.write('OFF\n%d %d 0\n' % (len(points), len(tris)))
        for p in points:
            o.write('%.17g %.17g %.17g\n' % p)
        for x in tris:
            o.write('3 %d %d %d\n' % x)
    print('%s: %d vertices, %d triangles (edges longer than %.4g split)' % (a.output, len(points), len(tris), h))


if __name__ == '__main__':
    main()
