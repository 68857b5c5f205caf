#!/usr/bin/env bash
# Benchmark of the global embedding optimisation (issue #20): per mesh, the patch area max/min of
# the layout as built and of the squares of the optimised seamless map (the area each unit square
# would get if the map were extracted), the symmetric Dirichlet energy before and after, and the
# stage's seconds; then the layout extracted from the map's iso-lines (`--embedding-extract`): its
# patch area max/min and corner angle deviation as ../shared/tools/check_layout.py --quality
# measures them, against the same figures of the layout without the stage, and the checker's
# verdict. Meshes: the shared eight, fertility, botijo, skull, 3holes and a generated body
# with 3 small handles (`quadcage generate handles -g 3`).
#   tools/bench/embedding.sh [BUILD_DIR] [ITERATIONS (default 30)] [MESH...]
# EMBEDDING_AREA_WEIGHT=W in the environment passes --embedding-area-weight W (default 0),
# EMBEDDING_CONFORMAL_WEIGHT=C --embedding-conformal-weight C (default 0),
# EMBEDDING_CONE_SWEEPS=N --embedding-cone-sweeps N (default 0).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
iterations=${2:-30}
shift $(( $# > 2 ? 2 : $# ))
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
meshes=../shared/data/meshes
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
list=("$@")
if [ ${#list[@]} -eq 0 ]; then
  "$qc" generate handles -g 3 -o "$work/handles3.ply" >/dev/null
  list=("$meshes/eight.off" "$meshes/fertility.off" "$meshes/botijo.off" "$meshes/skull.obj" "$meshes/3holes.off"
        "$work/handles3.ply")
fi
printf '| mesh | unknowns | energy before -> after | iterations (why stopped) | flipped | transition error | patch area max/min: layout -> optimised map | area unattributed | embedding s | layout s | extracted? | checker: area max/min, angle dev. mean (deg): without -> with the stage | vertices without -> with | check_layout |\n'
printf '|---|---:|---|---|---:|---:|---|---:|---:|---:|---|---|---|---|\n'
quality() {  # DIR MESH -> "ratio angle vertices verdict"
  local out
  out=$(../shared/tools/check_layout.py --patches "$1/layout.ply" --cage "$1/cage.obj" --input "$2" --quality 2>&1 || true)
  python3 -c '
import json, sys
text = sys.argv[1]
line = [l for l in text.splitlines() if l.startswith("{")]
if not line:
    print("? ? ? FAIL"); sys.exit()
q = json.loads(line[-1])
print("%.3g %.1f %d %s" % (q["patch_area_max_over_min"], q["corner_angle_mean_deviation_deg"], q["vertices"],
                          "PASS" if not q["failed"] else "FAIL:" + ",".join(q["failed"])))' "$out"
}
for m in "${list[@]}"; do
  name=$(basename "$m")
  start=$(date +%s.%N)
  "$qc" layout "$m" -o "$work/plain" -q >/dev/null 2>&1 || true
  if ! "$qc" layout "$m" -o "$work/out" --embedding-iterations "$iterations" --embedding-extract \
       --embedding-area-weight "${EMBEDDING_AREA_WEIGHT:-0}" --embedding-conformal-weight "${EMBEDDING_CONFORMAL_WEIGHT:-0}" \
       --embedding-cone-sweeps "${EMBEDDING_CONE_SWEEPS:-0}" >"$work/log" 2>&1; then
    printf '| %s | FAILED: %s |\n' "$name" "$(tail -1 "$work/log")"
    continue
  fi
  end=$(date +%s.%N)
  line=$(grep -o 'embedding: [0-9].*' "$work/log" | tail -1)
  kept=$(grep -o 'embedding: keeping .*' "$work/log" | tail -1 | sed 's/embedding: keeping //')
  read -r r0 a0 v0 c0 <<<"$(quality "$work/plain" "$m")"
  read -r r1 a1 v1 c1 <<<"$(quality "$work/out" "$m")"
  python3 - "$name" "$line" "$start" "$end" "$kept" "$r0 $a0 -> $r1 $a1" "$v0 -> $v1" "$c1" <<'PY'
import re, sys
name, line, start, end = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
kept, figures, vertices, verdict = sys.argv[5:9]
m = re.search(r"embedding: (\d+) iterations \((.*?)\), (\d+) unknowns, energy (\S+) -> (\S+), (\d+) flipped, "
              r"transition error (\S+), (\S+) s; patch area max/min (\S+) -> (\S+) if extracted \((\S+)% of", line)
if not m:
    print(f"| {name} | no embedding line: {line} |")
else:
    it, why, unk, e0, e1, fl, te, sec, before, after, lost = m.groups()
    print(f"| {name} | {unk} | {e0} -> {e1} | {it} ({why}) | {fl} | {te} | {before} -> {after} | {lost}% | {sec} | {end - start:.1f} | {kept} | {figures} | {vertices} | {verdict} |")
PY
done
