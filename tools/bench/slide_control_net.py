#!/usr/bin/python3
"""Slides a quad control net along a triangle mesh to even out its faces: each round every net
vertex moves towards the area-weighted mean of its faces' centroids, in the tangent plane of the
mesh at its closest point, and is projected back onto the mesh. An experiment of issue #20 (README,
"The level-3 control net slid to even out its faces"): fit the written net with
`quadcage fit MESH --cage NET.obj --level 0` and compare with the same net projected and not slid
(--rounds 0).

  tools/bench/slide_control_net.py --input MESH --net fitted_cage.obj -o NET.obj [--rounds N] [--step S]

Prints the net's face area max/min and standard deviation over mean before and after.
"""
import argparse
import sys

import numpy as np
from scipy.spatial import cKDTree

from shared_checkers import read_mesh, triangles


def closest_points(P, A, B, C):
    """Closest points on triangles (A, B, C) to points P, all [n, 3] (Ericson, Real-Time Collision
    Detection 5.1.5; check_fit.py's closest_on_triangles gives the distances only)."""
    ab, ac, ap, bp, cp = B - A, C - A, P - A, P - B, P - C
    d1, d2, d3, d4 = (ab * ap).sum(1), (ac * ap).sum(1), (ab * bp).sum(1), (ac * bp).sum(1)
    d5, d6 = (ab * cp).sum(1), (ac * cp).sum(1)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2

    def ratio(n, d):
        return n / np.where(np.abs(d) < 1e-300, 1e-300, d)

    den = va + vb + vc
    Q = A + ab * ratio(vb, den)[:, None] + ac * ratio(vc, den)[:, None]
    # The regions, least specific first: a later one overrides.
    regions = [
        ((va <= 0) & (d4 >= d3) & (d5 >= d6), B + (C - B) * ratio(d4 - d3, (d4 - d3) + (d5 - d6))[:, None]),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), A + ac * ratio(d2, d2 - d6)[:, None]),
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), A + ab * ratio(d1, d1 - d3)[:, None]),
        ((d6 >= 0) & (d5 <= d6), C), ((d3 >= 0) & (d4 <= d3), B), ((d1 <= 0) & (d2 <= 0), A)]
    for m, X in regions:
        Q[m] = X[m]
    return Q


class Projector:
    def __init__(self, V, T, k=24):
        self.A, self.B, self.C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
        n = np.cross(self.B - self.A, self.C - self.A)
        self.normal = n / np.maximum(np.linalg.norm(n, axis=1), 1e-300)[:, None]
        self.tree = cKDTree((self.A + self.B + self.C) / 3)
        self.k = min(k, len(T))

    def __call__(self, P):
        """The closest points on the mesh to P (among the k triangles of nearest centroids) and the
        normals of their triangles."""
        _, nn = self.tree.query(P, k=self.k)
        best, Q, N = np.full(len(P), np.inf), P.copy(), np.zeros_like(P)
        for j in range(self.k):
            t = nn[:, j]
            X = closest_points(P, self.A[t], self.B[t], self.C[t])
            d = ((X - P) ** 2).sum(1)
            m = d < best
            best[m], Q[m], N[m] = d[m], X[m], self.normal[t[m]]
        return Q, N


def vector_areas(V, F):
    """|half the cross product of the diagonals|: the weight of a quad's centroid (0 for a bow tie)."""
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 2]] - V[F[:, 0]], V[F[:, 3]] - V[F[:, 1]]), axis=1)


def fan_areas(V, F):
    """The areas of the four triangles from each quad's centroid to its sides, summed: the area reported."""
    c = V[F].mean(1)
    return sum(0.5 * np.linalg.norm(np.cross(V[F[:, i]] - c, V[F[:, (i + 1) % 4]] - c), axis=1) for i in range(4))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('--input', required=True, help='the triangle mesh the net slides on')
    ap.add_argument('--net', required=True, help='a quad control net (OBJ), e.g. fitted_cage.obj')
    ap.add_argument('-o', required=True, help='the net written, slid (OBJ)')
    ap.add_argument('--rounds', type=int, default=10)
    ap.add_argument('--step', type=float, default=0.25, help='fraction of the move taken a round')
    a = ap.parse_args()
    V, F, _ = read_mesh(a.input)
    project = Projector(np.asarray(V, float), triangles(F)[0])
    NV, NF, _ = read_mesh(a.net)
    if any(len(f) != 4 for f in NF):
        sys.exit('slide_control_net.py: %s: not a quad net' % a.net)
    F4 = np.array(NF, dtype=np.int64)
    P, N = project(np.asarray(NV, float))
    corner_of = F4.reshape(-1)  # net vertex of each face corner
    face_of = np.repeat(np.arange(len(F4)), 4)

    def report(when):
        ar = fan_areas(P, F4)
        print('%s: face area max/min %.3g, std/mean %.3f' % (when, ar.max() / ar.min(), ar.std() / ar.mean()))

    report('projected')
    for _ in range(a.rounds):
        area = vector_areas(P, F4)
        centroid = P[F4].mean(1)
        s, w = np.zeros_like(P), np.zeros(len(P))
        np.add.at(s, corner_of, centroid[face_of] * area[face_of, None])
        np.add.at(w, corner_of, area[face_of])
        d = s / w[:, None] - P
        d -= (d * N).sum(1)[:, None] * N
        P, N = project(P + a.step * d)
    report('slid %d rounds' % a.rounds)
    with open(a.o, 'w') as f:
        f.writelines('v %.9g %.9g %.9g\n' % tuple(p) for p in P)
        f.writelines('f %d %d %d %d\n' % tuple(q + 1) for q in F4)


if __name__ == '__main__':
    main()
