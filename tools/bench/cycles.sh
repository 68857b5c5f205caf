#!/usr/bin/env bash
# Benchmark of `quadcage cycles` (issue: orthogonal system): seconds and peak memory on botijo
# (82k triangles) and on botijo split 1-to-4 once (330k) and twice (1.3M). Targets on the 2-core
# machine: <= 5 s, <= 20 s, <= 60 s.
#   tools/bench/cycles.sh [BUILD_DIR] [MESH]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
mesh=${2:-../shared/data/meshes/botijo.off}
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
[ -f "$mesh" ] || { echo "mesh not found: $mesh" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$qc" subdivide "$mesh" -t 1 -o "$work/x1.ply" >/dev/null
"$qc" subdivide "$mesh" -t 2 -o "$work/x2.ply" >/dev/null

printf '%-28s %10s %8s %10s %10s %9s %9s\n' mesh triangles genus wall_s cycles_s peak_MiB checker
for m in "$mesh" "$work/x1.ply" "$work/x2.ply"; do
  out="$work/out_$(basename "$m")"
  start=$(date +%s.%N)
  "$qc" cycles "$m" -o "$out" -q >/dev/null
  end=$(date +%s.%N)
  check=skipped
  if [ -x ../shared/tools/check_cycles.py ] && [ -x /usr/bin/python3 ]; then
    if ../shared/tools/check_cycles.py --mesh "$out/layout.ply" --cycles "$out/cycles.json" >/dev/null; then check=PASS; else check=FAIL; fi
  fi
  python3 - "$out/report.json" "$(basename "$m")" "$start" "$end" "$check" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print('%-28s %10d %8d %10.2f %10.2f %9.0f %9s' % (sys.argv[2], r['input_triangles'], r['genus'],
      float(sys.argv[4]) - float(sys.argv[3]), r['seconds'], r['peak_memory_mib'], sys.argv[5]))
PY
done
