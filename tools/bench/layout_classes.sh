#!/usr/bin/env bash
# Issue 20's failure classes, generated (`quadcage generate`), each laid out and fitted by
# `quadcage fit` and checked from outside: ../shared/tools/check_layout.py --quality (patch area
# max/min, corner angle deviation on edge chords at 10% of their length) and check_fit.py (relative
# RMS and Hausdorff of limit.ply). Classes:
#   - long protrusions: `generate limbs` (genus 0, a cube over a figure with limbs), with fins
#     (thin, flat protrusions: `--fins`), and fins on a body with handles (`handles --fins`, a
#     creature with fins);
#   - a big smooth body with a few small handles: `generate handles -g G`; with relief of its own
#     (a figure's body with one small handle): `generate handles -g 1 --bumps 12`;
#   - genus concentrated in one region: `generate handles -g G --in-a-row` (for G = 1, the one
#     handle at the edge of the body's top);
#   - holes in a ring round a central handle, input_wheel's class: `generate wheel -g G`, with ribs
#     round the hub (input_wheel's fins): `--ribs 16`; tessellated as input_wheel is, as a CAD
#     system exports a solid (flat faces as fans of long, thin triangles): `--cad`, fitted with the
#     long edges split first (the default) and without (`--no-long-edge-splits`).
# On the CAD rows and the limbs and fins rows (whose triangles are stretched along them)
# check_fit.py's nearest-centroid search misjudges the distance to the long, thin triangles
# (README, "Shapes like the ones that fail"), so those rows also give, in brackets, its figures
# against the same surface with every edge longer than the median split
# (tools/bench/split_long_edges.py; a 1-to-4 split keeps the triangles as thin, and the error).
# Fit level 3, level 4 for genus 0 and 1 (6- and 4-quad cages). Issue 20's targets on every row:
# area max/min <= 4, fit RMS <= 1e-3 and Hausdorff <= 1e-2. The script reports; it asserts nothing.
#   tools/bench/layout_classes.sh [BUILD_DIR] [NAME...]
#     NAME...  only the rows whose name contains one of these (e.g. CAD); default: every row
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
shift || true
only=("$@")
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
[ -x ../shared/tools/check_layout.py ] || { echo "needs ../shared/tools/check_layout.py" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cases=(
  "limbs seed 1|limbs --limbs 4 --seed 1 -r 4||fine"
  "limbs seed 20|limbs --limbs 5 --seed 20 -r 4||fine"
  "limbs and fins|limbs --limbs 2 --fins 3 --seed 3 -r 5||fine"
  "handles g3 fins|handles -g 3 -r 3 --fins 3||fine"
  "handles g1|handles -g 1 -r 3"
  "handles g1 bumps|handles -g 1 -r 3 --bumps 12"
  "handles g1 at the edge|handles -g 1 -r 3 --in-a-row"
  "handles g2|handles -g 2 -r 3"
  "handles g3|handles -g 3 -r 3"
  "handles g8|handles -g 8 -r 3"
  "handles g3 in a row|handles -g 3 -r 3 --in-a-row"
  "handles g5 in a row|handles -g 5 -r 3 --in-a-row"
  "wheel g7|wheel -g 7 -r 3"
  "wheel g11|wheel -g 11 -r 3"
  "wheel g11 ribs|wheel -g 11 -r 3 --ribs 16"
  "wheel g7 CAD|wheel -g 7 -r 3 --cad||fine"
  "wheel g7 CAD, no splits|wheel -g 7 -r 3 --cad|--no-long-edge-splits|fine"
  "wheel g11 ribs CAD|wheel -g 11 -r 3 --ribs 16 --cad||fine"
  "wheel g11 ribs CAD, no splits|wheel -g 11 -r 3 --ribs 16 --cad|--no-long-edge-splits|fine"
)
# shellcheck source=tools/bench/fit_check_row.sh
. tools/bench/fit_check_row.sh
fit_check_header
for c in "${cases[@]}"; do
  IFS='|' read -r name args fit_flags fine <<<"$c"
  if [ ${#only[@]} -gt 0 ]; then
    wanted=0
    for o in "${only[@]}"; do [[ "$name" == *"$o"* ]] && wanted=1; done
    [ "$wanted" = 1 ] || continue
  fi
  mesh="$work/${name// /_}.ply"
  # shellcheck disable=SC2086
  "$qc" generate $args -o "$mesh" >/dev/null
  fit_check_row "$name" "$mesh" "$fit_flags" "$fine"
done
