#!/usr/bin/env python3
"""Writes a copy of a mesh whose vertices are moved at random, for tools/bench/perturbed.sh.

    jitter.py IN OUT.off AMPLITUDE SEED

IN is an ASCII OFF or OBJ triangle mesh. Each coordinate of each vertex moves by a uniform random
amount in [-AMPLITUDE, AMPLITUDE] times the mean edge length; the faces are kept, so the copy has
the input's connectivity and genus. SEED makes the copy reproducible (Python's own generator,
no numpy). The copy stands for another scan of the same shape: the same topology, (almost surely)
no two triangles coplanar, every edge a little longer or shorter.
"""
import math
import random
import sys


def read(path):
    points, faces = [], []
    if path.lower().endswith(".off"):
        tokens = open(path).read().split()
        if tokens[0] != "OFF":
            raise SystemExit(f"{path}: not an ASCII OFF file")
        nv, nf = int(tokens[1]), int(tokens[2])
        i = 4
        for _ in range(nv):
            points.append([float(x) for x in tokens[i:i + 3]])
            i += 3
        for _ in range(nf):
            n = int(tokens[i])
            faces.append([int(x) for x in tokens[i + 1:i + 1 + n]])
            i += 1 + n
    elif path.lower().endswith(".obj"):
        for line in open(path):
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                points.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                faces.append([int(x.split("/")[0]) - 1 for x in t[1:]])
    else:
        raise SystemExit(f"{path}: only ASCII OFF and OBJ are read")
    return points, faces


def main():
    if len(sys.argv) != 5:
        raise SystemExit(__doc__)
    src, dst, amplitude, seed = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
    points, faces = read(src)
    total, count = 0.0, 0
    for f in faces:
        for a, b in zip(f, f[1:] + f[:1]):
            total += math.dist(points[a], points[b])
            count += 1
    step = amplitude * total / max(count, 1)
    rng = random.Random(seed)
    with open(dst, "w") as out:
        out.write(f"OFF\n{len(points)} {len(faces)} 0\n")
        for p in points:
            out.write("%.9g %.9g %.9g\n" % tuple(x + rng.uniform(-step, step) for x in p))
        for f in faces:
            out.write(f"{len(f)} {' '.join(map(str, f))}\n")


if __name__ == "__main__":
    main()
