#!/usr/bin/env bash
# Benchmark and accuracy check of `quadcage fit` (issue #5): for each mesh, `fit --level K` for
# K = 0..3 (0..4 for genus 1), the reported relative symmetric RMS and Hausdorff next to those of
# the independent ../shared/tools/check_fit.py on the written limit.ply, seconds (layout + fit) and
# peak memory. Prints a markdown table.
#   tools/bench/fit.sh [BUILD_DIR] [MESH...]     (default: the issue's seven shared meshes)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
shift || true
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  for m in eight.off torus.obj kitten.off fertility.off 3holes.off botijo.off skull.obj; do meshes+=("../shared/data/meshes/$m"); done
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf '| mesh | level | control points | rel. RMS | rel. Hausdorff | check_fit RMS | check_fit Hausdorff | seconds (layout + fit) | peak MiB |\n'
printf '|---|---:|---:|---:|---:|---:|---:|---:|---:|\n'
for m in "${meshes[@]}"; do
  name=$(basename "$m")
  genus=$("$qc" info "$m" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["components"][0]["genus"])')
  top=3; [ "$genus" = 1 ] && top=4
  for k in $(seq 0 $top); do
    out="$work/$name.$k"
    if ! "$qc" fit "$m" -o "$out" --level "$k" -q >"$out.log" 2>&1; then
      printf '| %s | %d | | | | | | | FAILED: %s |\n' "$name" "$k" "$(tail -1 "$out.log")"; continue
    fi
    check='{}'
    if [ -x ../shared/tools/check_fit.py ] && [ -x /usr/bin/python3 ]; then
      check=$(../shared/tools/check_fit.py --input "$m" --surface "$out/limit.ply" 2>/dev/null | grep '^{' | tail -1 || echo '{}')
    fi
    python3 - "$out/report.json" "$name" "$k" "$check" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
l = r['levels'][-1]
try:
    c = json.loads(sys.argv[4])['relative']
    crms, chd = '%.3g' % c['rms'], '%.3g' % c['hausdorff']
except Exception:
    crms, chd = '-', '-'
print('| %s | %s | %d | %.3g | %.3g | %s | %s | %.1f + %.1f | %.0f |' % (sys.argv[2], sys.argv[3], l['control_points'],
      l['relative']['rms'], l['relative']['hausdorff'], crms, chd, r['seconds']['layout'], r['seconds']['fit'], r['peak_memory_mib']))
PY
  done
done
