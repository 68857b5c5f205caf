#!/usr/bin/env python3
"""Seed corpus of the loader fuzz targets (tests/fuzz), generated from small meshes.

usage: tools/fuzz_corpus.py OUT_DIR

Writes OUT_DIR/<target>/<name> for the targets obj, ply, off, stl, extras and cage: a tetrahedron,
a cube of quads and an octahedron in every variant each reader knows (OBJ corner forms, negative
indices and polygons; OFF with and without header; PLY ascii and binary of both endiannesses, with
face lists or triangle strips, mixed scalar types and the 'patch' / 'distance' properties; STL ascii
and binary), plus a few small hostile headers of the kinds found by hand (a property-less element
of count 2^63-1, a NaN patch). Nothing here is committed: tools/fuzz.sh runs this before fuzzing.
"""

import os
import struct
import sys

TETRA = ([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
         [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)])
CUBE = ([(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)],
        [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)])
OCTA = ([(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)],
        [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)])
SHAPES = {"tetra": TETRA, "cube": CUBE, "octa": OCTA}


def triangles(faces):
    for f in faces:
        for k in range(1, len(f) - 1):
            yield (f[0], f[k], f[k + 1])


def obj(points, faces, form="plain"):
    out = ["# seed\n", "o seed\n"]
    out += ["v %g %g %g\n" % p for p in points]
    if form == "vtvn":
        out += ["vt 0 0\n", "vn 0 0 1\n"]
    n = len(points)
    for f in faces:
        if form == "plain":
            corners = [str(v + 1) for v in f]
        elif form == "negative":
            corners = [str(v - n) for v in f]
        else:
            corners = ["%d/1/1" % (v + 1) for v in f]
        out.append("f " + " ".join(corners) + "\n")
    return "".join(out).encode()


def off(points, faces, header=True):
    out = ["OFF\n"] if header else []
    out.append("%d %d 0\n" % (len(points), len(faces)))
    out += ["%g %g %g\n" % p for p in points]
    out += ["%d %s\n" % (len(f), " ".join(map(str, f))) for f in faces]
    return "".join(out).encode()


def ply(points, faces, encoding="ascii", strips=False, extras=False):
    tris = list(triangles(faces))
    head = ["ply", "format %s 1.0" % encoding, "comment seed",
            "element vertex %d" % len(points), "property float x", "property double y", "property float z"]
    if extras:
        head.append("property float distance")
    if strips:
        head += ["element tristrips 1", "property list int int vertex_indices"]
    else:
        head += ["element face %d" % len(faces), "property list uchar int vertex_indices"]
        if extras:
            head.append("property int patch")
    head.append("end_header")
    text = ("\n".join(head) + "\n").encode()
    strip = []
    for t in tris:
        strip += list(t) + [-1]
    if encoding == "ascii":
        body = []
        for i, p in enumerate(points):
            body.append("%g %g %g" % p + (" %g" % (0.1 * i) if extras else ""))
        if strips:
            body.append("%d %s" % (len(strip), " ".join(map(str, strip))))
        else:
            for i, f in enumerate(faces):
                body.append("%d %s" % (len(f), " ".join(map(str, f))) + (" %d" % (i % 3) if extras else ""))
        return text + ("\n".join(body) + "\n").encode()
    e = "<" if encoding == "binary_little_endian" else ">"
    body = b""
    for i, p in enumerate(points):
        body += struct.pack(e + "fdf", *p) + (struct.pack(e + "f", 0.1 * i) if extras else b"")
    if strips:
        body += struct.pack(e + "i", len(strip)) + b"".join(struct.pack(e + "i", v) for v in strip)
    else:
        for i, f in enumerate(faces):
            body += struct.pack(e + "B", len(f)) + b"".join(struct.pack(e + "i", v) for v in f)
            if extras:
                body += struct.pack(e + "i", i % 3)
    return text + body


def stl_ascii(points, faces):
    out = ["solid seed\n"]
    for t in triangles(faces):
        out.append(" facet normal 0 0 0\n  outer loop\n")
        out += ["   vertex %g %g %g\n" % points[v] for v in t]
        out.append("  endloop\n endfacet\n")
    out.append("endsolid seed\n")
    return "".join(out).encode()


def stl_binary(points, faces):
    tris = list(triangles(faces))
    data = b"seed".ljust(80, b" ") + struct.pack("<I", len(tris))
    for t in tris:
        data += struct.pack("<3f", 0, 0, 0)
        for v in t:
            data += struct.pack("<3f", *points[v])
        data += b"\0\0"
    return data


HOSTILE_PLY = {
    "no_property_huge_count": b"ply\nformat ascii 1.0\nelement a 9223372036854775807\nend_header\n",
    "huge_vertex_count": b"ply\nformat binary_little_endian 1.0\nelement vertex 4294967296\n"
                         b"property float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0",
    "nan_patch": b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 b"element face 1\nproperty list uchar int vertex_indices\nproperty float patch\nend_header\n"
                 b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2 nan\n",
}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    seeds = {t: {} for t in ("obj", "ply", "off", "stl", "extras", "cage")}
    for name, (points, faces) in SHAPES.items():
        for form in ("plain", "negative", "vtvn"):
            seeds["obj"]["%s_%s.obj" % (name, form)] = obj(points, faces, form)
        seeds["off"][name + ".off"] = off(points, faces)
        seeds["off"][name + "_headerless.off"] = off(points, faces, header=False)
        for enc in ("ascii", "binary_little_endian", "binary_big_endian"):
            for strips in (False, True):
                data = ply(points, faces, enc, strips)
                seeds["ply"]["%s_%s%s.ply" % (name, enc, "_strips" if strips else "")] = data
            seeds["extras"]["%s_%s.ply" % (name, enc)] = ply(points, faces, enc, extras=True)
        seeds["stl"][name + "_ascii.stl"] = stl_ascii(points, faces)
        seeds["stl"][name + "_binary.stl"] = stl_binary(points, faces)
        seeds["cage"][name + ".obj"] = obj(points, faces)
        seeds["cage"][name + ".off"] = off(points, faces)
        seeds["cage"][name + ".ply"] = ply(points, faces, "binary_little_endian")
    for name, data in HOSTILE_PLY.items():
        seeds["ply"][name + ".ply"] = data
        seeds["extras"][name + ".ply"] = data
    for target, files in seeds.items():
        os.makedirs(os.path.join(root, target), exist_ok=True)
        for name, data in files.items():
            with open(os.path.join(root, target, name), "wb") as f:
                f.write(data)
    print("fuzz_corpus: %d seeds in %s" % (sum(len(f) for f in seeds.values()), root))


if __name__ == "__main__":
    main()
