#!/usr/bin/python3
"""What a fitted surface's error follows, patch by patch: the patch's area or the shape of its grid.

  patch_shape_error.py --input MESH --surface limit.ply --quads N [--samples S]

limit.ply (as `quadcage fit` writes it) tessellates each of the cage's N quads in turn, with the same
number of triangles each, uniformly in the quad's parameter square, so patch i is the i-th run of
triangles (the layout's patch i: the same order). Per patch this prints
- its area over the mean patch area;
- the anisotropy of its grid: per triangle, longest edge squared over (area times 4 / sqrt 3), 1 for
  an equilateral triangle and about r for a grid cell stretched r times; the patch's median and
  90th percentile (a patch stretched into a strip has cells of its own aspect ratio at every level);
- the RMS distance from its points to the input (check_fit.py's point-triangle distance over the
  triangles of nearest centroid, at the centroids of S limit triangles drawn by area; relative to
  the input's bounding-box diagonal);
then the correlation of that RMS with log area and with each anisotropy figure over the patches,
and the worst and best patches. Reports, asserts nothing. Where the input has long, thin triangles
(a CAD export's fans), check_fit.py's distances are too large (check_fit_exactness.py): use it on
scans and generated bodies.
"""
import argparse

import numpy as np

from shared_checkers import check_fit, read_mesh, triangles


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--input', required=True)
    ap.add_argument('--surface', required=True, help='limit.ply of a fit')
    ap.add_argument('--quads', type=int, required=True, help="the cage's quad count (level 0)")
    ap.add_argument('--samples', type=int, default=200000)
    ap.add_argument('--rows', type=int, default=8, help='worst and best patches listed')
    a = ap.parse_args()
    vi, fi, _ = read_mesh(a.input)
    ti, _ = triangles(fi)
    vs, fs, _ = read_mesh(a.surface)
    ts, _ = triangles(fs)
    if len(ts) % a.quads:
        raise SystemExit('%s: %d triangles is not a multiple of %d quads' % (a.surface, len(ts), a.quads))
    diag = float(np.linalg.norm(vi.max(0) - vi.min(0)))
    per = len(ts) // a.quads
    patch = np.arange(len(ts)) // per
    p0, p1, p2 = vs[ts[:, 0]], vs[ts[:, 1]], vs[ts[:, 2]]
    area = np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1) / 2
    longest = np.max([np.linalg.norm(p1 - p0, axis=1), np.linalg.norm(p2 - p1, axis=1),
                      np.linalg.norm(p0 - p2, axis=1)], axis=0)
    aspect = longest ** 2 / np.maximum(area * 4 / np.sqrt(3), 1e-300)
    # Distances at the centroids of triangles drawn by area (fixed seed): each patch is sampled in
    # proportion to its area, as check_fit.py samples the whole surface.
    rng = np.random.default_rng(7)
    pick = rng.choice(len(ts), size=min(a.samples, len(ts)), p=area / area.sum())
    d = check_fit.distances((p0[pick] + p1[pick] + p2[pick]) / 3, vi, ti)
    sq = np.bincount(patch[pick], d * d, minlength=a.quads)
    count = np.bincount(patch[pick], minlength=a.quads)
    patch_area = np.bincount(patch, area, minlength=a.quads)
    rel_area = patch_area / patch_area.mean()
    rms = np.sqrt(sq / np.maximum(count, 1)) / diag
    # Patch i is the i-th run of `per` triangles: one row each.
    median = np.median(aspect.reshape(a.quads, per), axis=1)
    p90 = np.quantile(aspect.reshape(a.quads, per), 0.9, axis=1)
    keep = count > 0
    corr = lambda x: float(np.corrcoef(x[keep], rms[keep])[0, 1])  # noqa: E731
    print('%s: %d patches; surface->input RMS %.3e over %d samples' % (
        a.surface, a.quads, np.sqrt((d * d).mean()) / diag, len(d)))
    print('correlation of the patches\' RMS with log area %.2f, anisotropy median %.2f, anisotropy 90%% %.2f' % (
        corr(np.log(rel_area)), corr(median), corr(p90)))
    order = np.argsort(-rms)
    for label, rows in (('worst', order[:a.rows]), ('best', order[::-1][:a.rows])):
        for i in rows:
            print('%-5s patch %3d  RMS %.3e  area/mean %6.2f  anisotropy median %6.2f  90%% %7.2f' % (
                label, i, rms[i], rel_area[i], median[i], p90[i]))


if __name__ == '__main__':
    main()
