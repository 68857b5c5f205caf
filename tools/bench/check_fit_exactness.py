#!/usr/bin/python3
"""Cross-checks ../shared/tools/check_fit.py's surface->input distances against exact ones.

  check_fit_exactness.py INPUT LIMIT_PLY [--samples N]

check_fit.py finds each sample's distance over the 24 input triangles whose centroids are nearest.
On an input with long, skinny triangles (a figure whose limbs are stretched icosphere triangles) the
closest triangle can have a far centroid, and the distance comes out too large. This script takes
check_fit.py's own samples of LIMIT_PLY (same sampler, same seed) and prints their distances to
INPUT both ways: check_fit.py's k-nearest-centroid search and an exact minimum over every input
triangle (brute force: small inputs only). Relative to INPUT's bounding-box diagonal.
"""
import argparse
import sys

import numpy as np

from shared_checkers import check_fit, read_mesh, triangles


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('input')
    ap.add_argument('surface')
    ap.add_argument('--samples', type=int, default=20000)
    a = ap.parse_args()
    vi, fi, _ = read_mesh(a.input)
    ti, _ = triangles(fi)
    vs, fs, _ = read_mesh(a.surface)
    ts, _ = triangles(fs)
    if len(ti) > 50000:
        sys.exit('the exact search is brute force: inputs up to 50000 triangles')
    p = check_fit.sample(vs, ts, a.samples, np.random.default_rng(7))[:a.samples]
    knn = check_fit.distances(p, vi, ti)
    a_, b_, c_ = vi[ti[:, 0]], vi[ti[:, 1]], vi[ti[:, 2]]
    exact = np.full(len(p), np.inf)
    for i in range(len(ti)):
        rep = lambda x: np.broadcast_to(x[i], p.shape)  # noqa: E731
        exact = np.minimum(exact, check_fit.closest_on_triangles(p, rep(a_), rep(b_), rep(c_)))
    diag = float(np.linalg.norm(vi.max(0) - vi.min(0)))
    rms = lambda d: float(np.sqrt((d ** 2).mean())) / diag  # noqa: E731
    print('surface->input over %d samples: check_fit k-nearest-centroid rms %.4g max %.4g; exact rms %.4g max %.4g; '
          '%d samples overestimated by more than 1e-3'
          % (len(p), rms(knn), knn.max() / diag, rms(exact), exact.max() / diag, int(np.sum(knn - exact > 1e-3 * diag))))


if __name__ == '__main__':
    main()
