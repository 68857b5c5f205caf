#!/usr/bin/env bash
# The layout built on a decimated copy (`--proxy-vertices N --proxy-above 0`) against the layout built
# on the input (`--proxy-vertices 0`):
# per mesh, `quadcage layout` both ways, with whether the copy's layout was carried onto the input
# (else the reason it fell back), check_layout.py --quality on both, vertices added and wall
# seconds. With --fit, then `quadcage fit` with the copy (tools/bench/fit_check_row.sh rows:
# check_layout.py and check_fit.py). Reports; asserts nothing.
#   tools/bench/proxy.sh [--fit] [--copy-only] [--vertices N] [BUILD_DIR] [MESH...]
#     N  the copy's vertices (default 10000)
#     --copy-only  skip the layout on the input (slow on inputs of hundreds of thousands of vertices)
#     MESH...  default: the shared meshes of genus >= 2 and botijo split 1-to-4 twice
set -euo pipefail
here=$(pwd)
cd "$(dirname "$0")/../.."
fit=0 n=10000 ways="input copy"
while [ $# -gt 0 ]; do
  case "$1" in
    --fit) fit=1; shift ;;
    --vertices) n=$2; shift 2 ;;
    --copy-only) ways=copy; shift ;;
    *) break ;;
  esac
done
build=${1:-build}
[ $# -gt 0 ] && shift
qc=$build/quadcage
[ -x "$qc" ] || { echo "no quadcage in $build" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=tools/bench/mesh_list.sh
. tools/bench/mesh_list.sh
mesh_list "$here" "$@"
if [ $# -eq 0 ]; then
  "$qc" subdivide ../shared/data/meshes/botijo.off -t 2 -o "$work/botijo_x16.ply" >/dev/null
  meshes+=("$work/botijo_x16.ply")
fi
quality() {  # DIR MESH -> "PASS area angle" or "FAIL ..."
  if ../shared/tools/check_layout.py --patches "$1/layout.ply" --cage "$1/cage.obj" --input "$2" --quality \
    >"$work/check" 2>&1; then
    python3 -c 'import json,sys; q=json.loads([l for l in open(sys.argv[1]) if l.startswith("{")][-1]); print("PASS | %.3g | %.1f" % (q["patch_area_max_over_min"], q["corner_angle_mean_deviation_deg"]))' "$work/check"
  else
    echo "FAIL: $(grep FAIL "$work/check" | head -1) | |"
  fi
}
added() { python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); print("%d (bound %d)" % (r["vertices_added"], r["vertices_added_bound"]))' "$1/report.json" 2>/dev/null || echo '?'; }
echo "copy: $n vertices"
echo '| mesh | build | check_layout | area max/min | angle dev. (deg) | vertices added | layout s | the copy |'
echo '|---|---|---|---:|---:|---:|---:|---|'
for mesh in "${meshes[@]}"; do
  name=$(basename "${mesh%.*}")
  for way in $ways; do
    flags=(--proxy-vertices 0)
    [ "$way" = copy ] && flags=(--proxy-vertices "$n" --proxy-above 0)
    start=$(date +%s.%N)
    if ! "$qc" layout "$mesh" -o "$work/$way" "${flags[@]}" >"$work/log" 2>&1; then
      echo "| $name | $way | FAILED: $(tail -1 "$work/log") | | | | | |"
      continue
    fi
    secs=$(python3 -c "import sys; print('%.2f' % (float(sys.argv[2]) - float(sys.argv[1])))" "$start" "$(date +%s.%N)")
    copy=''
    if [ "$way" = copy ]; then
      copy=$(grep -o 'proxy: carried onto the input [^(]*\|proxy: [^:]*; building on the input itself\|proxy: not carried onto the input ([^)]*)' "$work/log" | head -1 | sed 's/^proxy: //' || true)
      [ -z "$copy" ] && copy='not used (input too small)'
    fi
    echo "| $name | $way | $(quality "$work/$way" "$mesh") | $(added "$work/$way") | $secs | $copy |"
  done
done
if [ "$fit" = 1 ]; then
  # shellcheck source=tools/bench/fit_check_row.sh
  . tools/bench/fit_check_row.sh
  echo
  echo "fits with --proxy-vertices $n --proxy-above 0:"
  fit_check_header
  for mesh in "${meshes[@]}"; do fit_check_row "$(basename "${mesh%.*}")" "$mesh" "--proxy-vertices $n --proxy-above 0" no; done
fi
