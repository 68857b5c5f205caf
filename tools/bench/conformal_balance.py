#!/usr/bin/python3
"""How evenly a layout with these corners could spread the area if it kept every angle (issue #20).

  conformal_balance.py DIR [--greedy]

DIR is what `quadcage layout` (or `fit`) wrote; its layout.ply has the face property `patch`. A quad
layout is a flat metric with cones: every patch a unit square, each corner of degree d a cone of
curvature 2pi - d pi/2 (degree 5: -pi/2). The flat cone metric conformal to the surface (no angle
distortion at all) with its cones at the layout's corners is e^(2u) g, where u solves the discrete
Poisson equation L u = K_cones - K (L the cotangent Laplacian, K the angle defects; Ben-Chen,
Gotsman & Bunin 2008, "Conformal flattening by curvature prescription and metric scaling"). Where u
is small a unit square covers much surface, where it is large little: a layout that kept every
angle would give patch p a surface area proportional to S_p / F_p (its surface area over its area
in that metric). The script prints that ratio's max/min over the patches, the "conformal area
ratio" at these corners, beside the layout's own patch area max/min.

This does not bound check_layout.py's figures: they are the patch areas and the angles at the
corners only, and a patch stretched more one way than the other (a band) keeps its corner angles;
eight's layout has area max/min 2.09 and a conformal area ratio of 10.8. It measures how far the
corners stand from where an angle-preserving layout would want them, so that the balance has to
come from stretching the patches.

With --greedy it also places the same number of cones of the same curvature on the surface alone,
one at a time where u is largest (smallest for a positive cone; Ben-Chen et al.'s heuristic: a
negative cone lowers u most where it stands), ignoring which places a layout can put them in, and
prints the spread of u both ways as exp(2 (q98 - q02)), the 98th over the 2nd area-weighted
percentile of the local scale: a rough figure for what placing the cones elsewhere could give (greedy, so not a bound either way). u falls off
like a logarithm at a cone, so the spread depends on how fine the mesh is round the cones: compare
it between placements on one mesh, not between meshes.

Uses ../shared/tools/meshio.py to read the PLY. numpy and scipy.
"""
import argparse
import math
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', 'shared', 'tools'))
from meshio import read_ply, triangles  # noqa: E402


def geometry(V, T):
    """Cotangent Laplacian (positive semidefinite), angle defects, triangle areas."""
    a, b, c = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    n = len(V)
    rows, cols, vals = [], [], []
    angle_sum = np.zeros(n)
    for k in range(3):
        i, j, o = T[:, k], T[:, (k + 1) % 3], T[:, (k + 2) % 3]
        e1, e2 = V[i] - V[o], V[j] - V[o]
        cos = np.einsum('ij,ij->i', e1, e2)
        sin = np.linalg.norm(np.cross(e1, e2), axis=1)
        angle_sum += np.bincount(o, weights=np.arctan2(sin, cos), minlength=n)
        w = 0.5 * cos / np.maximum(sin, 1e-300)
        rows += [i, j, i, j]
        cols += [j, i, i, j]
        vals += [-w, -w, w, w]
    L = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))
    return L, 2 * math.pi - angle_sum, area


class Poisson:
    """Solves L u = f (sum f = 0) with u pinned at vertex 0, then centred."""

    def __init__(self, L):
        self.n = L.shape[0]
        self.lu = spla.splu(L[1:, 1:].tocsc())

    def solve(self, f):
        u = np.zeros(self.n)
        u[1:] = self.lu.solve(f[1:])
        return u - u.mean()


def spread(u, vertex_area):
    """exp(2 (q98 - q02)) of u, area-weighted percentiles."""
    order = np.argsort(u)
    cum = np.cumsum(vertex_area[order]) / vertex_area.sum()
    lo = u[order[np.searchsorted(cum, 0.02)]]
    hi = u[order[min(np.searchsorted(cum, 0.98), len(u) - 1)]]
    return math.exp(2 * (hi - lo))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('dir')
    ap.add_argument('--greedy', action='store_true')
    args = ap.parse_args()
    path = os.path.join(args.dir, 'layout.ply')
    if not os.path.isfile(path):
        sys.exit(f'{path}: no such file (DIR must be what `quadcage layout` or `fit` wrote)')
    V, F, props = read_ply(path)
    T, src = triangles(F)
    if 'patch' not in props:
        sys.exit(f'{path}: no face property "patch" (not a layout)')
    patch = np.asarray(props['patch'], dtype=np.int64)[src]
    n = len(V)
    L, K, area = geometry(V, T)
    vertex_area = np.bincount(T.ravel(), weights=np.repeat(area / 3, 3), minlength=n)

    # Corners: vertices where 3 or more patches meet; their degree is the number of patches.
    patches_at = [set() for _ in range(n)]
    for t, (i, j, k) in enumerate(T):
        for v in (i, j, k):
            patches_at[v].add(patch[t])
    degree = np.array([len(s) for s in patches_at])
    corners = np.nonzero(degree >= 3)[0]
    cone = np.zeros(n)
    cone[corners] = 2 * math.pi - degree[corners] * math.pi / 2
    if abs(cone.sum() - K.sum()) > 1e-6 * max(1.0, abs(K.sum())):
        sys.exit(f'{path}: the corners\' curvature {cone.sum():.6f} is not the surface\'s {K.sum():.6f}')
    poisson = Poisson(L)
    u = poisson.solve(cone - K)

    ut = u[T].mean(axis=1)
    npatch = patch.max() + 1
    surface = np.bincount(patch, weights=area, minlength=npatch)
    flat = np.bincount(patch, weights=area * np.exp(2 * ut), minlength=npatch)
    density = surface / flat
    print(f'{args.dir}: {n} vertices, {npatch} patches, {len(corners)} corners')
    print(f'  patch area max/min of the layout: {surface.max() / surface.min():.3g}')
    print(f'  conformal area ratio at these corners (max/min of S_p/F_p): {density.max() / density.min():.3g}')
    print(f'  scale spread exp(2 (q98 - q02)) at these corners: {spread(u, vertex_area):.3g}')
    if args.greedy:
        # As many cones of each curvature, placed one at a time where u is largest (a negative
        # cone) or smallest (a positive one: a sphere's cube corners).
        placed = np.zeros(n)
        curvatures = sorted(cone[corners])
        for kappa in curvatures:
            w = poisson.solve(placed - K + (cone.sum() - placed.sum()) * vertex_area / vertex_area.sum())
            v = int(np.argmax(w) if kappa < 0 else np.argmin(w))
            placed[v] += kappa
        w = poisson.solve(placed - K)
        print(f'  scale spread with {len(curvatures)} cones placed greedily: {spread(w, vertex_area):.3g}')


if __name__ == '__main__':
    main()
