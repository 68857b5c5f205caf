#!/usr/bin/env bash
# Level-3 fits (level 4 for genus 0 and 1, whose cages have 6 and 4 quads) of each mesh under one or
# more sets of `quadcage fit` flags, each measured by the independent checkers:
# ../shared/tools/check_fit.py (relative RMS and Hausdorff of limit.ply) and check_layout.py
# --quality (patch area max/min, corner angle deviation mean, verdict), with the layout's and the
# fit's seconds from report.json. Issue 20's fit targets: RMS <= 1e-3 and Hausdorff <= 1e-2. With
# --embedding-extract among a variant's flags, `kept` says whether the extracted layout was kept.
# Prints one markdown table, a row per mesh and variant; reports, asserts nothing.
#   tools/bench/fit_compare.sh [BUILD_DIR] [--variant LABEL=FLAGS]... [MESH...]
#     --variant   a label and the flags of one fit, e.g. --variant 'rounds 8=--rounds 8'; repeatable;
#                 default: one variant, 'default=' (no flags)
#     MESH...     default: the nine shared meshes of genus >= 1 and generated shapes of issue 20's
#                 failure classes (a big body with 1 small handle, plain and with bumps, and with
#                 3; 4 handles in a row; a figure with 5 limbs; a wheel of genus 7)
# Timings are the machine's at the time: run it idle for figures worth quoting.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build
if [ $# -gt 0 ] && [ -d "$1" ]; then build=$1; shift; fi
labels=() flag_sets=() list=()
while [ $# -gt 0 ]; do
  case "$1" in
    --variant)
      case "${2:-}" in *=*) ;; *) echo "fit_compare.sh: --variant takes LABEL=FLAGS" >&2; exit 2 ;; esac
      labels+=("${2%%=*}"); flag_sets+=("${2#*=}"); shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) list+=("$1"); shift ;;
  esac
done
if [ ${#labels[@]} -eq 0 ]; then labels=(default); flag_sets=(""); fi
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
shared=../shared
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ ${#list[@]} -eq 0 ]; then
  "$qc" generate handles -g 1 -o "$work/handles1.ply" >/dev/null
  "$qc" generate handles -g 1 --bumps 12 -o "$work/handles1bumps.ply" >/dev/null
  "$qc" generate handles -g 3 -o "$work/handles3.ply" >/dev/null
  "$qc" generate handles -g 4 --in-a-row -o "$work/handles4row.ply" >/dev/null
  "$qc" generate limbs --limbs 5 -o "$work/limbs5.ply" >/dev/null
  "$qc" generate wheel -g 7 -r 3 -o "$work/wheel7.ply" >/dev/null
  for m in eight torus kitten 3holes fertility skull botijo boot input_wheel; do
    list+=("$(ls "$shared/data/meshes/$m".* | head -1)")
  done
  list+=("$work/handles1.ply" "$work/handles1bumps.ply" "$work/handles3.ply" "$work/handles4row.ply" "$work/limbs5.ply"
         "$work/wheel7.ply")
fi
printf '| mesh | genus | level | variant | kept | area max/min | angle dev. (deg) | check_layout | RMS | Hausdorff | targets | layout s | fit s |\n'
printf '|---|---:|---:|---|---|---:|---:|---|---:|---:|---|---:|---:|\n'
for m in "${list[@]}"; do
  name=$(basename "$m")
  genus=$("$qc" info "$m" --json | python3 -c 'import json,sys; print(sum(c["genus"] or 0 for c in json.load(sys.stdin)["components"]))')
  level=3
  [ "$genus" -le 1 ] && level=4
  for i in "${!labels[@]}"; do
    label=${labels[$i]}
    read -r -a flags <<<"${flag_sets[$i]}"
    out="$work/$name.$i"
    if ! "$qc" fit "$m" --level "$level" "${flags[@]}" -o "$out" >"$work/log" 2>&1; then
      printf '| %s | %s | %s | %s | FAILED: %s |\n' "$name" "$genus" "$level" "$label" "$(tail -1 "$work/log")"
      continue
    fi
    kept=-
    case " ${flag_sets[$i]} " in
      *" --embedding-extract "*) kept=$(grep -q 'keeping the extracted layout' "$work/log" && echo yes || echo no) ;;
    esac
    layout_q=$("$shared/tools/check_layout.py" --patches "$out/layout.ply" --cage "$out/cage.obj" --input "$m" \
      --quality 2>&1 | grep '^{' | tail -1 || true)
    fit_q=$("$shared/tools/check_fit.py" --input "$m" --surface "$out/limit.ply" --report "$out/report.json" 2>&1 |
      grep '^{' | tail -1 || true)
    python3 - "$name" "$genus" "$level" "$label" "$kept" "$layout_q" "$fit_q" "$out/report.json" <<'PY'
import json, sys
name, genus, level, label, kept, lq, fq, report = sys.argv[1:]
l = json.loads(lq) if lq else {}
f = json.loads(fq) if fq else {}
r = json.load(open(report))
rms = f.get('relative', {}).get('rms', float('nan'))
h = f.get('relative', {}).get('hausdorff', float('nan'))
verdict = ('PASS' if not l.get('failed') else 'FAIL') if l else '?'
targets = 'met' if rms <= 1e-3 and h <= 1e-2 else 'missed'
print('| %s | %s | %s | %s | %s | %.3g | %.1f | %s | %.3e | %.3e | %s | %.1f | %.1f |' % (
    name, genus, level, label, kept, l.get('patch_area_max_over_min', float('nan')),
    l.get('corner_angle_mean_deviation_deg', float('nan')), verdict, rms, h, targets,
    r['seconds']['layout'], r['seconds']['fit']))
PY
    rm -rf "$out"
  done
done
