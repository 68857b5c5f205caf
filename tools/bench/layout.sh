#!/usr/bin/env bash
# Benchmark of `quadcage layout` (issue #4): seconds, peak memory and the layout quality figures on
# every shared mesh, and on botijo split 1-to-4 twice (1.3M triangles). Every layout is checked by
# ../shared/tools/check_layout.py (--patches, --cage, --input). Targets on the 2-core machine:
# botijo <= 10 s; botijo at 1.3M triangles <= 120 s and <= 4 GiB.
# With --plates FROM TO: instead, the generated plates (`quadcage generate plate -g G`) of genus
# FROM..TO, each with an hour's timeout (the issue's "generated solids of genus 0..20").
# When `blender` is on PATH (and not with --plates), the same run also times QuadriFlow remeshing
# botijo to 1000 quads (tools/bench/quadriflow.py, its own seconds) three times, our botijo layout
# twice more, and prints the ratio of the medians of our wall times and QuadriFlow's (issue #20's
# speed target: at most 2).
#   tools/bench/layout.sh [BUILD_DIR] [--no-large | --plates FROM TO]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
large=1
plates=()
[ "${2:-}" = "--no-large" ] && large=0
if [ "${2:-}" = "--plates" ]; then
  large=0
  plates=($(seq "${3:?--plates FROM TO}" "${4:?--plates FROM TO}"))
fi
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
meshes=../shared/data/meshes
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

list=(bunny.obj igea.ply kitten.off torus.obj eight.off skull.obj 3holes.off fertility.off botijo.off input_wheel.off boot.obj)
[ ${#plates[@]} -gt 0 ] && list=()
if [ $large = 1 ]; then
  "$qc" subdivide "$meshes/botijo.off" -t 2 -o "$work/botijo_x16.ply" >/dev/null
fi

printf '| mesh | input triangles | genus | quads | corners (degree) | wall s | peak MiB | vertices added | patch area max/min | corner angle dev. mean / max (deg) | distortion mean / max | edge length / sqrt(area) | check_layout |\n'
printf '|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---|\n'
run() {
  local m=$1 name=$2
  local out="$work/out_$name"
  local start end
  start=$(date +%s.%N)
  if ! timeout 3600 "$qc" layout "$m" -o "$out" -q >"$work/$name.log" 2>&1; then
    printf '| %s | | | | | | | | | | | | FAILED: %s |\n' "$name" "$(tail -1 "$work/$name.log")"
    return
  fi
  end=$(date +%s.%N)
  python3 -c "print($end - $start)" >"$work/wall_$name"
  local input_arg=(--input "$m")
  # The checker's reader does not know PLY tristrips (igea): check the rest without --input.
  if head -c 2000 "$m" | grep -aq "element tristrips"; then input_arg=(); fi
  local check=skipped
  if [ -x ../shared/tools/check_layout.py ] && [ -x /usr/bin/python3 ]; then
    if ../shared/tools/check_layout.py --patches "$out/layout.ply" --cage "$out/cage.obj" "${input_arg[@]}" >"$work/$name.check" 2>&1; then
      check=PASS; else check="FAIL: $(grep FAIL "$work/$name.check" | head -1)"; fi
    [ ${#input_arg[@]} -eq 0 ] && check="$check (no --input: tristrips)"
  fi
  python3 - "$out/report.json" "$name" "$start" "$end" "$check" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
q = r['quality']
deg = ', '.join('%s x %s' % (v, k) for k, v in sorted(r['degree_histogram'].items()))
tri = r['triangles'] - 2 * r['vertices_added']  # closed surface: T = 2V - 4 + 4g, so T_in = T - 2 * added
print('| %s | %d | %d | %d | %s | %.2f | %.0f | %d | %.3g | %.1f / %.1f | %.2f / %.3g | %.2f | %s |' % (
    sys.argv[2], tri, r['genus'], r['quads'], deg, float(sys.argv[4]) - float(sys.argv[3]), r['peak_memory_mib'],
    r['vertices_added'], q['patch_area_max_over_min'], q['corner_angle_mean_deviation_deg'],
    q['corner_angle_max_deviation_deg'], q['distortion_mean'], q['distortion_max'], q['edge_length_over_sqrt_area'],
    sys.argv[5]))
PY
}
for m in "${list[@]}"; do run "$meshes/$m" "$m"; done
[ $large = 1 ] && run "$work/botijo_x16.ply" "botijo split twice"
for g in "${plates[@]}"; do
  "$qc" generate plate -g "$g" -o "$work/plate_$g.obj" >/dev/null
  run "$work/plate_$g.obj" "plate genus $g"
done
if [ ${#plates[@]} -eq 0 ] && command -v blender >/dev/null; then
  # Three runs of each, alternating, and the ratio of the medians: single runs of either moved the
  # ratio by more than its target's margin on the 2-core VM (2.11 and 2.75 minutes apart).
  ok=1
  for i in 1 2 3; do
    if [ "$i" -gt 1 ]; then
      start=$(date +%s.%N)
      "$qc" layout "$meshes/botijo.off" -o "$work/out_botijo_$i" -q >/dev/null 2>&1 || ok=0
      end=$(date +%s.%N)
      python3 -c "print($end - $start)" >"$work/wall_botijo.off.$i"
    else
      cp "$work/wall_botijo.off" "$work/wall_botijo.off.1" 2>/dev/null || ok=0
    fi
    blender -b --factory-startup -noaudio --python-exit-code 1 --python tools/bench/quadriflow.py -- \
      "$meshes/botijo.off" "$work/botijo_qf_$i.obj" 1000 0 >"$work/qf.log" 2>&1 || { ok=0; break; }
  done
  if [ $ok = 1 ]; then
    python3 - "$work" <<'PY'
import json, statistics, sys
w = sys.argv[1]
ours = [float(open('%s/wall_botijo.off.%d' % (w, i)).read()) for i in (1, 2, 3)]
qf = [json.load(open('%s/botijo_qf_%d.obj.json' % (w, i))) for i in (1, 2, 3)]
qs = [q['seconds'] for q in qf]
print('\nbotijo: our layout %s s, median %.2f; QuadriFlow to %d quads (target 1000) %s s, median %.2f; '
      'ratio of the medians %.2f (target <= 2)'
      % (', '.join('%.2f' % x for x in ours), statistics.median(ours), qf[0]['quads_out'],
         ', '.join('%.2f' % x for x in qs), statistics.median(qs), statistics.median(ours) / statistics.median(qs)))
PY
  else
    echo; echo "botijo: QuadriFlow or our layout failed: $(tail -1 "$work/qf.log")"
  fi
elif [ ${#plates[@]} -eq 0 ]; then
  echo; echo "botijo: QuadriFlow not timed: blender is not on PATH (Debian's package blender)"
fi
exit 0
