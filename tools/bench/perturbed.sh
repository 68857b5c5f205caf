#!/usr/bin/env bash
# `quadcage layout` on the shared meshes and on jittered copies of them (tools/bench/jitter.py:
# each coordinate of every vertex moved by up to AMPLITUDE times the mean edge length, the faces
# kept), which stand for other scans of the same shapes: the project's results are also checked on
# scans it does not have.
# Per mesh and seed (seed 0: the file itself): vertices added against issue 20's bound (a quarter of
# the input's vertices plus 200 per corner), ../shared/tools/check_layout.py (--patches, --cage,
# --input) and its patch area max/min and corner angle deviation. Reports; asserts nothing.
#   tools/bench/perturbed.sh [BUILD_DIR] [--amplitude A] [--seeds N] [MESH...]
#     --amplitude A  default 0.05
#     --seeds N      jittered copies per mesh, seeds 1..N (default 2)
#     MESH...        default: the shared meshes of genus >= 1 in ASCII OFF or OBJ
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=$here/build
amplitude=0.05
seeds=2
meshes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --amplitude) amplitude=$2; shift 2 ;;
    --seeds) seeds=$2; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) if [ -d "$1" ]; then build=$(realpath "$1"); else meshes+=("$(realpath "$1")"); fi; shift ;;
  esac
done
cd "$here"
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
[ -x ../shared/tools/check_layout.py ] || { echo "needs ../shared/tools/check_layout.py" >&2; exit 2; }
shared=../shared/data/meshes
if [ ${#meshes[@]} -eq 0 ]; then
  for m in kitten.off torus.obj eight.off skull.obj 3holes.off fertility.off botijo.off input_wheel.off boot.obj; do
    meshes+=("$shared/$m")
  done
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '| mesh | seed | genus | input vertices | vertices added | bound | within | check_layout | area max/min | angle dev. mean (deg) | layout s |\n'
printf '|---|---:|---:|---:|---:|---:|---|---|---:|---:|---:|\n'
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  for seed in $(seq 0 "$seeds"); do
    input="$m"
    if [ "$seed" -gt 0 ]; then
      input="$work/${name%.*}_$seed.off"
      python3 tools/bench/jitter.py "$m" "$input" "$amplitude" "$seed"
    fi
    out="$work/out"
    rm -rf "$out"
    start=$(date +%s.%N)
    if ! "$qc" layout "$input" -o "$out" -q >"$work/log" 2>&1; then
      printf '| %s | %s | | | | | | FAILED: %s | | | |\n' "$name" "$seed" "$(tail -1 "$work/log")"
      continue
    fi
    end=$(date +%s.%N)
    check=PASS
    ../shared/tools/check_layout.py --patches "$out/layout.ply" --cage "$out/cage.obj" --input "$input" \
      --quality >"$work/check" 2>&1 || check="FAIL: $(grep FAIL "$work/check" | head -1)"
    python3 - "$out/report.json" "$work/check" "$name" "$seed" "$check" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
q = json.loads(open(sys.argv[2]).read().strip().splitlines()[-1])
added, bound = r['vertices_added'], r['vertices_added_bound']
print('| %s | %s | %d | %d | %d | %d | %s | %s | %.3g | %.1f | %.1f |' % (
    sys.argv[3], sys.argv[4], r['genus'], r['input_vertices'], added, bound,
    'yes' if r['vertices_added_within_bound'] else '**no**', sys.argv[5], q['patch_area_max_over_min'],
    q['corner_angle_mean_deviation_deg'], float(sys.argv[7]) - float(sys.argv[6])))
PY
  done
done
