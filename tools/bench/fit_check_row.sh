# Sourced by the bench scripts that fit meshes as a user would and check them from outside
# (layout_classes.sh, meshes.sh). Run from the checkout's top, with $qc (the quadcage binary) and
# $work (a scratch folder) set.
#
# fit_check_header: the table's two header lines.
# fit_check_row NAME MESH FIT_FLAGS FINE: `quadcage fit MESH --level L FIT_FLAGS` (L = 3, 4 for
# genus 0 and 1), then ../shared/tools/check_layout.py --quality and check_fit.py on its output;
# with FINE = fine also check_fit.py against MESH with its long edges split
# (tools/bench/split_long_edges.py), in brackets. Prints one row. Its "folds" column is the share of
# limit.ply's area on folds (report.json's limit_tessellation.folded_area_fraction: neighbouring
# triangles whose normals point apart), the input's own share in brackets; "turned over" is the
# share whose normal points against the input's (limit_tessellation.inverted_area_fraction).

fit_check_header() {
  printf '| shape | triangles | genus | quads | level | area max/min | angle dev. mean (deg) | check_layout | RMS | Hausdorff | check_fit RMS / Hausdorff | folds %% (input %%) | turned over %% | layout s | fit s |\n'
  printf '|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---|---:|---:|---:|---:|\n'
}

fit_check_row() {
  local name=$1 mesh=$2 fit_flags=$3 fine=$4
  local genus level out check fitcheck finecheck
  genus=$("$qc" info "$mesh" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["components"][0]["genus"])')
  level=3
  [ "$genus" -le 1 ] && level=4
  out="$work/out_${name// /_}"
  # shellcheck disable=SC2086
  if ! "$qc" fit "$mesh" --level "$level" $fit_flags -q -o "$out" >"$work/log" 2>&1; then
    printf '| %s | | %s | | %s | | | FAILED: %s | | | | | | | |\n' "$name" "$genus" "$level" "$(tail -1 "$work/log")"
    return 0
  fi
  check=PASS
  ../shared/tools/check_layout.py --patches "$out/layout.ply" --cage "$out/cage.obj" --input "$mesh" --quality \
    >"$work/check" 2>&1 || check="FAIL: $(grep FAIL "$work/check" | head -1)"
  fitcheck=$(../shared/tools/check_fit.py --input "$mesh" --surface "$out/limit.ply" 2>/dev/null | grep '^{' | tail -1 || echo '{}')
  finecheck='{}'
  if [ "$fine" = fine ]; then
    tools/bench/split_long_edges.py "$mesh" "$work/fine.off" >/dev/null
    finecheck=$(../shared/tools/check_fit.py --input "$work/fine.off" --surface "$out/limit.ply" 2>/dev/null | grep '^{' | tail -1 || echo '{}')
  fi
  python3 - "$out/report.json" "$work/check" "$name" "$check" "$fitcheck" "$finecheck" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
q = json.loads([l for l in open(sys.argv[2]) if l.startswith('{')][-1])
l = r['levels'][-1]
f = json.loads(sys.argv[5])
fc = '%.3g / %.3g' % (f['relative']['rms'], f['relative']['hausdorff']) if 'relative' in f else '?'
g = json.loads(sys.argv[6])
if 'relative' in g:
    fc += ' (%.3g / %.3g)' % (g['relative']['rms'], g['relative']['hausdorff'])
tri = q['triangles'] - 2 * r['layout']['vertices_added']
t = r.get('limit_tessellation', {})
folds = '%.2f (%.2f)' % (100 * t['folded_area_fraction'], 100 * t['input_folded_area_fraction']) \
    if 'folded_area_fraction' in t else '?'
folds += ' | %.2f' % (100 * t['inverted_area_fraction']) if 'inverted_area_fraction' in t else ' | ?'
print('| %s | %d | %d | %d | %d | %.3g | %.1f | %s | %.3g | %.3g | %s | %s | %.2f | %.2f |' % (
    sys.argv[3], tri, r['genus'], r['quads'], l['level'], q['patch_area_max_over_min'],
    q['corner_angle_mean_deviation_deg'], sys.argv[4], l['relative']['rms'], l['relative']['hausdorff'], fc,
    folds, r['seconds']['layout'], r['seconds']['fit']))
PY
}
