#!/usr/bin/env bash
# What the global embedding stage (issue #20) does to the fit: per mesh, `quadcage fit` at the
# issue's level (3; 4 for genus 0 and 1) without and with `--embedding-iterations N
# --embedding-extract`, each measured by the independent checkers: ../shared/tools/check_fit.py
# (relative RMS and Hausdorff) and check_layout.py --quality (patch area max/min, corner angle
# deviation mean, verdict), with the layout's and the fit's seconds from report.json and whether
# the stage kept its extracted layout. The issue's targets: RMS <= 1e-3 and Hausdorff <= 1e-2.
# Meshes (default): the nine shared meshes of genus >= 1 of issue #19's comparison, and generated
# shapes of the failure class: a big body with 1 and 3 small handles, 4 handles in a row.
#   tools/bench/embedding_fit.sh [BUILD_DIR] [ITERATIONS (default 30)] [MESH...]
# Timings are the machine's at the time: run it idle for figures worth quoting.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
iterations=${2:-30}
shift $(($# > 2 ? 2 : $#))
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
shared=../shared
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
list=("$@")
if [ ${#list[@]} -eq 0 ]; then
  "$qc" generate handles -g 1 -o "$work/handles1.ply" >/dev/null
  "$qc" generate handles -g 3 -o "$work/handles3.ply" >/dev/null
  "$qc" generate handles -g 4 --in-a-row -o "$work/handles4row.ply" >/dev/null
  for m in eight torus kitten 3holes fertility skull botijo boot input_wheel; do
    list+=("$(ls "$shared/data/meshes/$m".* | head -1)")
  done
  list+=("$work/handles1.ply" "$work/handles3.ply" "$work/handles4row.ply")
fi
printf '| mesh | genus | level | stage | kept | area max/min | angle dev. (deg) | check_layout | RMS | Hausdorff | targets | layout s | fit s |\n'
printf '|---|---:|---:|---|---|---:|---:|---|---:|---:|---|---:|---:|\n'
for m in "${list[@]}"; do
  name=$(basename "$m")
  genus=$("$qc" info "$m" 2>/dev/null | sed -n "s/.* genus \([0-9]*\) .*/\1/p" | head -1)
  level=3
  [ "${genus:-2}" -le 1 ] && level=4
  for stage in off on; do
    out="$work/$name.$stage"
    flags=()
    [ "$stage" = on ] && flags=(--embedding-iterations "$iterations" --embedding-extract)
    if ! "$qc" fit "$m" --level "$level" "${flags[@]}" -o "$out" >"$work/log" 2>&1; then
      printf '| %s | %s | %s | %s | FAILED: %s |\n' "$name" "$genus" "$level" "$stage" "$(tail -1 "$work/log")"
      continue
    fi
    kept=-
    [ "$stage" = on ] && kept=$(grep -q 'keeping the extracted layout' "$work/log" && echo yes || echo no)
    layout_q=$("$shared/tools/check_layout.py" --patches "$out/layout.ply" --cage "$out/cage.obj" --input "$m" \
      --quality 2>&1 | grep '^{' | tail -1 || true)
    fit_q=$("$shared/tools/check_fit.py" --input "$m" --surface "$out/limit.ply" --report "$out/report.json" 2>&1 |
      grep '^{' | tail -1 || true)
    python3 - "$name" "$genus" "$level" "$stage" "$kept" "$layout_q" "$fit_q" "$out/report.json" <<'PY'
import json, sys
name, genus, level, stage, kept, lq, fq, report = sys.argv[1:]
l = json.loads(lq) if lq else {}
f = json.loads(fq) if fq else {}
r = json.load(open(report))
rms = f.get('relative', {}).get('rms', float('nan'))
h = f.get('relative', {}).get('hausdorff', float('nan'))
verdict = ('PASS' if not l.get('failed') else 'FAIL') if l else '?'
targets = 'met' if rms <= 1e-3 and h <= 1e-2 else 'missed'
print('| %s | %s | %s | %s | %s | %.3g | %.1f | %s | %.3e | %.3e | %s | %.1f | %.1f |' % (
    name, genus, level, stage, kept, l.get('patch_area_max_over_min', float('nan')),
    l.get('corner_angle_mean_deviation_deg', float('nan')), verdict, rms, h, targets,
    r['seconds']['layout'], r['seconds']['fit']))
PY
  done
done
