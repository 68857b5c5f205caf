#!/usr/bin/env bash
# `quadcage fit` on coarser copies of the shared scans (tools/bench/decimate.cpp: OpenMesh's quadric
# decimation to a vertex count, the genus kept), which stand for scans of the same shapes taken at
# other resolutions: the project's results are also checked on scans it does not have.
# Per copy: ../shared/tools/check_layout.py (--patches, --cage, --input) and its patch area max/min
# and corner angle deviation, the fit at level 3 (level 4 for genus 0 and 1) by our report and by
# ../shared/tools/check_fit.py (relative RMS / Hausdorff; in brackets against the copy with its
# long edges split, tools/bench/split_long_edges.py, where the checker's nearest-centroid search
# misjudges a coarse copy's large triangles), the fit's rounds at that level and the command's
# seconds. Reports; asserts nothing.
#   tools/bench/decimated.sh [BUILD_DIR] [--fit-args 'ARGS'] [MESH:VERTICES...]
#     --fit-args  more arguments for every `quadcage fit` (e.g. '--extra-rounds 0')
#     default copies: eight 300, kitten 500, fertility 600 and 1500, 3holes 800, skull 1500 and 5000,
#                     botijo 1200, 3000 and 10000, boot 6000, input_wheel 8000
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=$here/build
fit_args=
copies=()
while [ $# -gt 0 ]; do
  case "$1" in
    --fit-args) fit_args=$2; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) if [ -d "$1" ]; then build=$(realpath "$1"); else copies+=("$1"); fi; shift ;;
  esac
done
cd "$here"
qc="$build/quadcage"
dec="$build/decimate_bench"
[ -x "$qc" ] && [ -x "$dec" ] || { echo "build first: $qc or $dec not found" >&2; exit 2; }
[ -x ../shared/tools/check_layout.py ] && [ -x ../shared/tools/check_fit.py ] ||
  { echo "needs ../shared/tools/check_layout.py and check_fit.py" >&2; exit 2; }
shared=../shared/data/meshes
if [ ${#copies[@]} -eq 0 ]; then
  copies=(eight.off:300 kitten.off:500 fertility.off:600 fertility.off:1500 3holes.off:800 skull.obj:1500
          skull.obj:5000 botijo.off:1200 botijo.off:3000 botijo.off:10000 boot.obj:6000 input_wheel.off:8000)
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '| copy | genus | check_layout | area max/min | angle dev. (deg) | level | rounds | ours: RMS / Hausdorff | check_fit.py: RMS / Hausdorff | fit s |\n'
printf '|---|---:|---|---:|---:|---:|---:|---|---|---:|\n'
for c in "${copies[@]}"; do
  mesh=${c%%:*} vertices=${c##*:}
  [ -f "$mesh" ] || mesh=$shared/$mesh
  name="$(basename "${mesh%.*}") $vertices"
  input="$work/copy.obj"
  if ! "$dec" "$mesh" "$input" "$vertices" >"$work/log" 2>&1; then  # OpenMesh talks on stderr
    printf '| %s | | FAILED to decimate: %s | | | | | | | |\n' "$name" "$(tail -1 "$work/log")"
    continue
  fi
  genus=$("$qc" info "$input" | grep -o 'genus [0-9]*' | head -1 | cut -d' ' -f2)
  level=3
  [ "$genus" -le 1 ] && level=4
  out="$work/out"
  rm -rf "$out"
  start=$(date +%s.%N)
  # shellcheck disable=SC2086  # --fit-args is a list of arguments
  if ! "$qc" fit "$input" -o "$out" --level "$level" $fit_args -q >"$work/log" 2>&1; then
    printf '| %s | %s | FAILED: %s | | | | | | | |\n' "$name" "$genus" "$(tail -1 "$work/log")"
    continue
  fi
  end=$(date +%s.%N)
  check=PASS
  ../shared/tools/check_layout.py --patches "$out/layout.ply" --cage "$out/cage.obj" --input "$input" \
    --quality >"$work/check" 2>&1 || check="FAIL: $(grep FAIL "$work/check" | head -1)"
  ../shared/tools/check_fit.py --input "$input" --surface "$out/limit.ply" >"$work/fit" 2>&1 || true
  tools/bench/split_long_edges.py "$input" "$work/fine.off" >/dev/null
  ../shared/tools/check_fit.py --input "$work/fine.off" --surface "$out/limit.ply" >"$work/finefit" 2>&1 || true
  python3 - "$out/report.json" "$work/check" "$work/fit" "$work/finefit" "$name" "$genus" "$check" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
q = json.loads(open(sys.argv[2]).read().strip().splitlines()[-1])
def relative(path):
    rows = [l for l in open(path) if l.startswith('{')]
    return json.loads(rows[-1])['relative'] if rows else None
cf, fine = relative(sys.argv[3]), relative(sys.argv[4])
lv = r['levels'][-1]
checked = '%.3e / %.3e' % (cf['rms'], cf['hausdorff']) if cf else 'n/a'
if fine:
    checked += ' (%.3e / %.3e)' % (fine['rms'], fine['hausdorff'])
print('| %s | %s | %s | %.3g | %.1f | %d | %d | %.3e / %.3e | %s | %.1f |' % (
    sys.argv[5], sys.argv[6], sys.argv[7], q['patch_area_max_over_min'], q['corner_angle_mean_deviation_deg'],
    lv['level'], lv['iterations'], lv['relative']['rms'], lv['relative']['hausdorff'], checked,
    float(sys.argv[9]) - float(sys.argv[8])))
PY
done
