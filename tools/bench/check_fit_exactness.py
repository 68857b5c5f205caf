#!/usr/bin/python3
"""Cross-checks ../shared/tools/check_fit.py's figures against exact distances on its own samples.

  check_fit_exactness.py INPUT LIMIT_PLY [--samples N] [--floor F]

check_fit.py finds each sample's distance over the 24 triangles whose centroids are nearest. Where
the other surface has long, skinny triangles (a figure whose limbs are stretched icosphere
triangles, a CAD export's fans such as input_wheel's) the closest triangle can have a far
centroid, and the distance comes out too large. This script draws check_fit.py's own samples (same
sampler, same seed, same count: both directions, as check_fit.py does) and measures again exactly
every sample the checker puts above F times INPUT's bounding-box diagonal (default 0: every
sample): over every triangle whose centroid lies within the checker's distance plus the triangle's
own reach (its largest centroid-to-vertex distance), which holds every triangle that can be nearer.
The checker's estimate is never below the exact distance, so with F > 0 the exact RMS printed is
an upper bound and the exact Hausdorff distance is exact wherever it is above F.

Prints, per direction and symmetric, the checker's figures and the exact ones, relative to INPUT's
bounding-box diagonal, as check_fit.py's "relative rms ... hausdorff ..." line.
"""
import argparse

import numpy as np
from scipy.spatial import cKDTree

from shared_checkers import check_fit, read_mesh, triangles


def exact_distances(p, d, v, t, floor):
    """d (the checker's distances of p to triangles t of v) made exact where above floor."""
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    cent = (a + b + c) / 3
    reach = np.max([np.linalg.norm(x - cent, axis=1) for x in (a, b, c)], axis=0)
    # Triangles reaching more than 8 times the median are tried one by one (their own reach); the
    # ball round a sample then needs only the reach of the others, which keeps it small on a mesh
    # with a few very long triangles.
    long_ = reach > 8 * np.median(reach)
    short_idx, long_idx = np.where(~long_)[0], np.where(long_)[0]
    reach_short = float(reach[short_idx].max()) if len(short_idx) else 0.0
    tree = cKDTree(cent[short_idx])
    d = d.copy()
    todo = np.where(d > floor)[0]
    for j in todo:
        near_long = long_idx[np.linalg.norm(cent[long_idx] - p[j], axis=1) <= d[j] + reach[long_idx]]
        cand = np.concatenate([short_idx[tree.query_ball_point(p[j], d[j] + reach_short)], near_long])
        if len(cand):
            q = np.broadcast_to(p[j], (len(cand), 3))
            d[j] = min(d[j], float(check_fit.closest_on_triangles(q, a[cand], b[cand], c[cand]).min()))
    return d, len(todo)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('input')
    ap.add_argument('surface')
    ap.add_argument('--samples', type=int, default=100000, help="check_fit.py's --samples (default its own)")
    ap.add_argument('--floor', type=float, default=0.0,
                    help='measure again only samples the checker puts above this fraction of the diagonal')
    a = ap.parse_args()
    vi, fi, _ = read_mesh(a.input)
    ti, _ = triangles(fi)
    vs, fs, _ = read_mesh(a.surface)
    ts, _ = triangles(fs)
    diag = float(np.linalg.norm(vi.max(0) - vi.min(0)))
    # The checker's draws, in its order (input first, then the surface).
    rng = np.random.default_rng(7)
    p_in = check_fit.sample(vi, ti, a.samples, rng)
    p_out = check_fit.sample(vs, ts, a.samples, rng)
    k_in = check_fit.distances(p_in, vs, ts)
    k_out = check_fit.distances(p_out, vi, ti)
    floor = a.floor * diag
    e_in, n_in = exact_distances(p_in, k_in, vs, ts, floor)
    e_out, n_out = exact_distances(p_out, k_out, vi, ti, floor)

    def rms(d):
        return float(np.sqrt((d ** 2).mean())) / diag

    for name, d_in, d_out in (('check_fit.py', k_in, k_out), ('exact', e_in, e_out)):
        both = np.concatenate([d_in, d_out])
        print('%-12s input->surface rms %.4g max %.4g; surface->input rms %.4g max %.4g; relative rms %.3e hausdorff %.3e'
              % (name, rms(d_in), d_in.max() / diag, rms(d_out), d_out.max() / diag, rms(both), both.max() / diag))
    print('measured again: %d of %d input samples (%d lower by more than 1e-3 of the diagonal), '
          '%d of %d surface samples (%d)'
          % (n_in, len(p_in), int(np.sum(k_in - e_in > 1e-3 * diag)), n_out, len(p_out),
             int(np.sum(k_out - e_out > 1e-3 * diag))))


if __name__ == '__main__':
    main()
