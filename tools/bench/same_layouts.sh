#!/usr/bin/env bash
# Whether two builds make the same layouts: `quadcage layout` with each on every mesh, then cmp of
# layout.ply, cycles.json, cage.json, cage.obj and cage_level1.obj, and each build's S-cycle choices
# (the "S-cycles: ... keeping ..." lines, with their scores and the scores' seconds) and layout
# seconds. For a change that must keep the layouts (a faster score, a faster search). Reports;
# asserts nothing.
#   tools/bench/same_layouts.sh BUILD_A BUILD_B [MESH...]
#     BUILD_A, BUILD_B  build folders (with quadcage in them) or quadcage binaries
#     MESH...  default: the shared meshes of genus >= 2 and generated bodies with handles, wheels
#              and plates (`quadcage generate`, with BUILD_A)
set -euo pipefail
here=$(pwd)
cd "$(dirname "$0")/../.."
binary() { if [ -d "$1" ]; then echo "$1/quadcage"; else echo "$1"; fi; }
a=$(binary "${1:?BUILD_A}")
b=$(binary "${2:?BUILD_B}")
shift 2
for q in "$a" "$b"; do [ -x "$q" ] || { echo "not a quadcage binary: $q" >&2; exit 2; }; done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=tools/bench/mesh_list.sh
. tools/bench/mesh_list.sh
mesh_list "$here" "$@"
if [ $# -eq 0 ]; then
  while read -r name args; do
    # shellcheck disable=SC2086
    "$a" generate $args -o "$work/$name.ply" >/dev/null
    meshes+=("$work/$name.ply")
  done <<'LIST'
handles_g2 handles -g 2 -r 3
handles_g3 handles -g 3 -r 3
handles_g3_row handles -g 3 -r 3 --in-a-row
handles_g5_row handles -g 5 -r 3 --in-a-row
wheel_g7 wheel -g 7 -r 3
wheel_g11_ribs wheel -g 11 -r 3 --ribs 16
plate_g4 plate -g 4
plate_g8 plate -g 8
plate_g12 plate -g 12
LIST
fi
builds=("$a" "$b")
sides=(a b)
same=0
for m in "${meshes[@]}"; do
  name=$(basename "${m%.*}")
  seconds=()
  for i in 0 1; do
    start=$(date +%s.%N)
    "${builds[$i]}" layout "$m" -o "$work/${sides[$i]}" >/dev/null 2>"$work/${sides[$i]}.log"
    end=$(date +%s.%N)
    seconds[$i]=$(python3 -c "print('%.2f' % ($end - $start))")
  done
  verdict=same
  for f in layout.ply cycles.json cage.json cage.obj cage_level1.obj; do
    cmp -s "$work/a/$f" "$work/b/$f" || verdict="DIFFER ($f)"
  done
  [ "$verdict" = same ] && same=$((same + 1))
  echo "== $name: $verdict; layout s ${seconds[0]} / ${seconds[1]}"
  for side in a b; do
    grep -o 'S-cycles: .*keeping.*' "$work/$side.log" | sed "s/^/  $side: /" || true
  done
done
echo "same layouts on $same of ${#meshes[@]} meshes"
