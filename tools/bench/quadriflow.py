"""Remesh a mesh with QuadriFlow inside Blender: the peer column of `quadcage bench`.

    blender -b --factory-startup --python-exit-code 1 --python tools/bench/quadriflow.py -- IN.obj OUT.obj TARGET_FACES [SEED]

Imports IN (OBJ; PLY, STL and ASCII OFF are accepted too), runs bpy.ops.object.quadriflow_remesh(target_faces=N,
seed=SEED) (blocking when called from Python; SEED, QuadriFlow's random seed, defaults to 0), exports
the result as OBJ (polygons kept) to OUT and writes OUT.json with {"seconds": QuadriFlow's own time,
"faces_in", "faces_out", "quads_out", "target_faces", "seed", "blender"}. Exits non-zero with one line
on stderr when QuadriFlow fails (Blender then leaves the mesh unchanged, i.e. still triangles).
"""
import json
import os
import sys
import time

import bpy


def fail(message):
    sys.stderr.write("quadriflow: error: " + message + "\n")
    sys.stderr.flush()
    raise SystemExit(1)


def import_off(path):
    """Blender has no OFF importer: reads the (ASCII) OFF's vertices and polygons into a new object."""
    words = []
    with open(path) as f:
        for line in f:
            words += line.split("#", 1)[0].split()
    if not words or words[0] != "OFF":
        fail("%s: not an OFF file (its first word is not OFF)" % path)
    nv, nf = int(words[1]), int(words[2])
    at = 4
    verts = []
    for _ in range(nv):
        verts.append(tuple(float(w) for w in words[at:at + 3]))
        at += 3
    faces = []
    for _ in range(nf):
        k = int(words[at])
        faces.append(tuple(int(w) for w in words[at + 1:at + 1 + k]))
        at += 1 + k
    mesh = bpy.data.meshes.new(os.path.basename(path))
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    bpy.context.scene.collection.objects.link(bpy.data.objects.new(mesh.name, mesh))


def main(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) not in (3, 4):
        fail("usage: blender -b --python quadriflow.py -- IN OUT TARGET_FACES [SEED]")
    src, dst, target = args[0], args[1], int(args[2])
    seed = int(args[3]) if len(args) == 4 else 0
    if target < 1:
        fail("TARGET_FACES must be >= 1, got %d" % target)
    if seed < 0:
        fail("SEED must be >= 0, got %d" % seed)

    # The factory scene holds a cube, a camera and a light: remove them.
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)

    ext = os.path.splitext(src)[1].lower()
    if ext == ".obj":
        bpy.ops.wm.obj_import(filepath=src)
    elif ext == ".ply":
        bpy.ops.import_mesh.ply(filepath=src)
    elif ext == ".stl":
        bpy.ops.import_mesh.stl(filepath=src)
    elif ext == ".off":
        import_off(src)
    else:
        fail("unsupported input %s (OBJ, PLY, STL or OFF)" % src)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if len(meshes) != 1:
        fail("expected one mesh object after importing %s, found %d" % (src, len(meshes)))
    obj = meshes[0]
    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    faces_in = len(obj.data.polygons)

    start = time.perf_counter()
    bpy.ops.object.quadriflow_remesh(target_faces=target, use_mesh_symmetry=False, use_preserve_sharp=False,
                                     use_preserve_boundary=False, smooth_normals=False, seed=seed)
    seconds = time.perf_counter() - start

    obj = bpy.context.view_layer.objects.active
    polys = obj.data.polygons
    quads = sum(1 for p in polys if len(p.vertices) == 4)
    if len(polys) > 0 and quads == 0:
        fail("QuadriFlow failed: the mesh is unchanged (%d faces, none a quad)" % len(polys))

    bpy.ops.wm.obj_export(filepath=dst, export_selected_objects=True, export_uv=False, export_normals=False,
                          export_materials=False, export_triangulated_mesh=False, apply_modifiers=False)
    with open(dst + ".json", "w") as f:
        json.dump({"seconds": seconds, "faces_in": faces_in, "faces_out": len(polys), "quads_out": quads,
                   "target_faces": target, "seed": seed, "blender": bpy.app.version_string}, f)
        f.write("\n")
    print("quadriflow: %d faces in, %d faces out (%d quads) for target %d, seed %d in %.3f s"
          % (faces_in, len(polys), quads, target, seed, seconds))


main(sys.argv)
