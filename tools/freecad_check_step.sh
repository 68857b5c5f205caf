#!/usr/bin/env bash
# Imports a quadcage STEP/IGES export into FreeCAD (freecadcmd, Debian's freecad 0.20) and checks it:
#   tools/freecad_check_step.sh FILE [FACES [VOLUME]]
# Prints FreeCAD's view as one JSON line and exits 0 on "freecad_check: PASS", 1 otherwise
# (2 when freecadcmd is missing). The test suite does not need FreeCAD; this is a manual check.
set -euo pipefail
if [ $# -lt 1 ]; then echo "usage: $0 FILE [FACES [VOLUME]]" >&2; exit 2; fi
command -v freecadcmd >/dev/null || { echo "freecad_check: freecadcmd not found (apt-get install freecad)" >&2; exit 2; }
here="$(cd "$(dirname "$0")" && pwd)"
out="$(QC_CAD_FILE="$(realpath "$1")" QC_FACES="${2:-}" QC_VOLUME="${3:-}" freecadcmd "$here/freecad_check_step.py" 2>&1)"
# FreeCAD's progress output shares lines with ours: pick the JSON object and the verdict out of it.
echo "$out" | grep -oE '\{"file".*\}' || { echo "$out" >&2; exit 1; }
echo "$out" | grep -oE 'freecad_check: .*'
echo "$out" | grep -q 'freecad_check: PASS'
