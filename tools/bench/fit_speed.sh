#!/usr/bin/env bash
# Speed of the fit stage (issue #19): `quadcage fit --level 3` on botijo (82k triangles) and on botijo
# split 1-to-4 twice (1.3M triangles). Prints, per run, the fit's seconds by level and by stage
# (report.json), the layout's seconds beside it, wall time and peak memory of the whole command
# (/usr/bin/time), and which BLAS libblas.so.3 resolves to (CHOLMOD's dense kernels run on it).
# Targets on the 2-core machine: botijo fit <= 7 s; 1.3M fit <= 15 s with the command <= 2 GiB.
# Run it on an otherwise idle machine: timings on 2 cores shift by 10% or more with other load.
# With --ceres, botijo is fitted a second time with --solver ceres (the rounds through ceres::Solve),
# to show what the direct solver changes; its fit must end at the same errors up to rounding.
#   tools/bench/fit_speed.sh [BUILD_DIR] [--no-large] [--ceres]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
[ -x /usr/bin/time ] || { echo "needs /usr/bin/time (Debian package: time)" >&2; exit 2; }
meshes=../shared/data/meshes
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "libblas.so.3 -> $(readlink -f /usr/lib/x86_64-linux-gnu/libblas.so.3 2>/dev/null || echo '?')"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
large=1 ceres=0
for arg in "${@:2}"; do
  case "$arg" in
    --no-large) large=0 ;;
    --ceres) ceres=1 ;;
    *) echo "unknown option: $arg" >&2; exit 2 ;;
  esac
done
inputs=("$meshes/botijo.off")
solvers=(direct)
[ "$ceres" = 1 ] && inputs+=("$meshes/botijo.off") && solvers+=(ceres)
if [ "$large" = 1 ]; then
  "$qc" subdivide "$meshes/botijo.off" -t 2 -o "$work/botijo_x16.ply" >/dev/null
  inputs+=("$work/botijo_x16.ply")
  solvers+=(direct)
fi
for k in "${!inputs[@]}"; do
  m=${inputs[$k]} solver=${solvers[$k]}
  out="$work/$(basename "$m").$solver.out"
  /usr/bin/time -f "%e %M" -o "$work/time.txt" "$qc" fit "$m" --level 3 --solver "$solver" -q -o "$out" >/dev/null
  read -r wall kib <"$work/time.txt"
  python3 - "$out/report.json" "$(basename "$m") (--solver $solver)" "$wall" "$kib" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
s = r['seconds']
print('%s: fit %.2f s, layout %.2f s, wall %s s, peak %.0f MiB' % (sys.argv[2], s['fit'], s['layout'], sys.argv[3],
      float(sys.argv[4]) / 1024))
tot = {}
for l in r['levels']:
    t = l['seconds']
    for k in ('parameterization', 'evaluation', 'closest_points', 'solve'):
        tot[k] = tot.get(k, 0) + t[k]
    print('  level %d: %5.2f s (parameterisation %.2f, evaluation %.2f, closest points %.2f, solve %.2f); '
          'relative rms %.3e, hausdorff %.3e' % (l['level'], t['total'], t['parameterization'], t['evaluation'],
          t['closest_points'], t['solve'], l['relative']['rms'], l['relative']['hausdorff']))
print('  by stage: ' + ', '.join('%s %.2f s' % kv for kv in tot.items()))
PY
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
