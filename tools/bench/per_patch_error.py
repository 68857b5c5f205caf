#!/usr/bin/python3
"""Where a fit's error lies, patch by patch of its layout, against another fit of the same input
(the peer's, at equal control points): the distance of each input vertex to each limit surface
(check_fit.py's exact point-triangle distance over the nearest triangles by centroid), grouped by
the layout patch the vertex lies in. Prints one row a patch, by patch area: its area over the mean,
each fit's RMS there (relative to the input's diagonal), their ratio, and the patch's share of the
first fit's summed squared error. Reports, asserts nothing.

  per_patch_error.py --input MESH --layout layout.ply --surface limit.ply --other OTHER_limit.ply

With a `quadcage bench` folder (peer_compare.sh -o DIR): layout and surface in
DIR/level3/meshes/NAME/level3/, the peer's surface in DIR/level3/meshes/NAME/peer/level3/fit/.
The layout must keep the input's vertices first, as `quadcage` writes it.
"""
import argparse
import sys

import numpy as np

from shared_checkers import check_fit, read_mesh, triangles


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--input', required=True)
    ap.add_argument('--layout', required=True, help="layout.ply with the face property 'patch'")
    ap.add_argument('--surface', required=True, help='limit.ply of the fit on that layout')
    ap.add_argument('--other', required=True, help='limit.ply of the fit compared with')
    a = ap.parse_args()
    vi, _, _ = read_mesh(a.input)
    lv, lf, props = read_mesh(a.layout)
    if 'patch' not in props:
        sys.exit('per_patch_error.py: %s has no face property patch' % a.layout)
    lt, source = triangles(lf)
    patch = np.asarray(props['patch'])[source]
    n = len(vi)
    if len(lv) < n or not np.allclose(lv[:n], vi):
        sys.exit('per_patch_error.py: %s does not start with the vertices of %s' % (a.layout, a.input))
    vertex_patch = np.full(len(lv), -1)
    for k in range(3):
        vertex_patch[lt[:, k]] = patch
    vertex_patch = vertex_patch[:n]
    corners = lv[lt]
    area = np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1) / 2
    patch_area = np.bincount(patch, weights=area)
    diagonal = np.linalg.norm(vi.max(0) - vi.min(0))
    dist = []
    for path in (a.surface, a.other):
        vs, fs, _ = read_mesh(path)
        ts, _ = triangles(fs)
        dist.append(check_fit.distances(vi, vs, ts) / diagonal)
    total = [(d ** 2).sum() for d in dist]
    print('input vertices: RMS %.3e against %.3e, ratio %.2f' %
          (np.sqrt(total[0] / n), np.sqrt(total[1] / n), np.sqrt(total[0] / total[1])))
    print('| area / mean | RMS | RMS other | ratio | share of the squared error |')
    print('|---:|---:|---:|---:|---:|')
    rows = []
    for p in range(len(patch_area)):
        m = vertex_patch == p
        if not m.any():
            continue
        r = [np.sqrt((d[m] ** 2).mean()) for d in dist]
        rows.append((patch_area[p] / patch_area.mean(), r[0], r[1], (dist[0][m] ** 2).sum() / total[0]))
    for s, r0, r1, share in sorted(rows):
        print('| %.2f | %.2e | %.2e | %.2f | %.1f%% |' % (s, r0, r1, r0 / r1, 100 * share))


if __name__ == '__main__':
    main()
