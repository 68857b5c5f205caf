"""Real-client check of a quadcage STEP/IGES export (issue 22), run inside FreeCAD's console:

    QC_CAD_FILE=surface.step [QC_FACES=10] [QC_VOLUME=0.68] freecadcmd tools/freecad_check_step.py

(or tools/freecad_check_step.sh FILE [FACES [VOLUME]]). Imports the file the way FreeCAD's File >
Import does (Import.insert for STEP, Part.insert for IGES), then prints one JSON line with what
FreeCAD sees: solids, shells, faces, whether every shell is closed, Shape.isValid(), area and
volume, and a verdict line "freecad_check: PASS" or "freecad_check: FAIL: <why>" (freecadcmd does
not pass an exit code on, so the wrapper reads that line). A FAIL is: no solid or more than one, a
shell that is not closed, an invalid shape, a face count other than QC_FACES, or a volume more than
1e-6 (relative) from QC_VOLUME.
"""
import json
import os
import sys
import time

import FreeCAD
import Part


def main():
    path = os.environ.get("QC_CAD_FILE", "")
    if not path or not os.path.isfile(path):
        print("freecad_check: FAIL: QC_CAD_FILE=%r is not a file" % path)
        return
    t0 = time.time()
    doc = FreeCAD.newDocument("qc")
    ext = os.path.splitext(path)[1].lower()
    if ext in (".step", ".stp"):
        import Import
        Import.insert(path, doc.Name)
    else:
        Part.insert(path, doc.Name)
    doc.recompute()
    shapes = [o.Shape for o in doc.Objects if hasattr(o, "Shape") and not o.Shape.isNull()]
    if not shapes:
        print("freecad_check: FAIL: FreeCAD imported no shape from %s" % path)
        return
    shape = shapes[0] if len(shapes) == 1 else Part.makeCompound(shapes)
    seconds = time.time() - t0
    result = {
        "file": path,
        "freecad": ".".join(FreeCAD.Version()[:3]),
        "objects": len(shapes),
        "solids": len(shape.Solids),
        "shells": len(shape.Shells),
        "faces": len(shape.Faces),
        "edges": len(shape.Edges),
        "vertices": len(shape.Vertexes),
        "shells_closed": all(s.isClosed() for s in shape.Shells),
        "valid": shape.isValid(),
        "area": shape.Area,
        "volume": shape.Volume,
        "import_seconds": seconds,
    }
    print(json.dumps(result))
    problems = []
    if result["solids"] != 1:
        problems.append("%d solids" % result["solids"])
    if not result["shells_closed"]:
        problems.append("a shell is not closed")
    if not result["valid"]:
        problems.append("Shape.isValid() is False")
    want_faces = os.environ.get("QC_FACES")
    if want_faces and int(want_faces) != result["faces"]:
        problems.append("%d faces, expected %s" % (result["faces"], want_faces))
    want_volume = os.environ.get("QC_VOLUME")
    if want_volume and abs(result["volume"] / float(want_volume) - 1) > 1e-6:
        problems.append("volume %.9g, expected %s" % (result["volume"], want_volume))
    print("freecad_check: " + ("PASS" if not problems else "FAIL: " + "; ".join(problems)))


main()
