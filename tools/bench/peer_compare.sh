#!/usr/bin/env bash
# The equal-control-point comparison of issue #19: our cage against a QuadriFlow cage, both fitted by
# our fitter, at level 3 (level 4 for genus 1). Runs `quadcage bench --levels 3` on the meshes of
# genus other than 1 and `--levels 4` on those of genus 1 (no pictures), so the figures are the
# bench's own peer fit (see README, Benchmarks), then prints one markdown table from both bench.json:
# ours and peer, control points, relative RMS and Hausdorff, the ratios ours / peer (they count only
# when the control-point counts are within 10%), the worst and median ratio, and the QuadriFlow
# attempts that were not used as they were.
#   tools/bench/peer_compare.sh [--check] [--embedding] [--turned-over-weight W] [-o DIR | --from DIR]
#                               [BUILD_DIR] [MESH...]
#     --check     also run ../shared/tools/check_fit.py on both limit.ply files (slow on big meshes)
#     --embedding our layouts with the embedding stage: `bench --embedding-iterations 30
#                 --embedding-extract` (issue #20; the peer's fit is unchanged)
#     --turned-over-weight W  every fit, ours and the peer's, with `fit --turned-over-weight W`
#     -o DIR      keep the bench folders in DIR (default: a new temporary folder, kept and printed)
#     --from DIR  run nothing: print the table from an earlier run's DIR (e.g. to add --check)
#     MESH...     default: the nine shared meshes of genus >= 1
set -euo pipefail
cd "$(dirname "$0")/../.."
check=0
out=
reuse=0
flags=()
while [ $# -gt 0 ]; do
  case "$1" in
    --check) check=1; shift ;;
    --embedding) flags+=(--embedding-iterations 30 --embedding-extract); shift ;;
    --turned-over-weight) flags+=(--turned-over-weight "${2:?--turned-over-weight needs a value}"); shift 2 ;;
    -o) out=$2; shift 2 ;;
    --from) out=$2; reuse=1; shift 2 ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    *) break ;;
  esac
done
build=build
if [ $# -gt 0 ] && [ -d "$1" ]; then build=$1; shift; fi
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  for m in eight.off torus.obj kitten.off 3holes.off fertility.off skull.obj botijo.off boot.obj input_wheel.off; do
    meshes+=("../shared/data/meshes/$m")
  done
fi
[ -n "$out" ] || out=$(mktemp -d /tmp/peer_compare.XXXXXX)
mkdir -p "$out"
command -v blender >/dev/null || echo "note: blender not on PATH: the peer columns will say 'not installed'" >&2

# Genus (summed over components) decides the level.
level3=() level4=()
for m in "${meshes[@]}"; do
  g=$("$qc" info "$m" --json | python3 -c 'import json,sys; print(sum(c["genus"] or 0 for c in json.load(sys.stdin)["components"]))')
  if [ "$g" = 1 ]; then level4+=("$m"); else level3+=("$m"); fi
done

start=$SECONDS
echo "peer_compare: ${#meshes[@]} meshes, outputs in $out ($(date -u '+%Y-%m-%d %H:%M:%S') UTC)" >&2
runs=()
wall=-1
if [ $reuse = 1 ]; then
  for k in 3 4; do [ -f "$out/level$k/bench.json" ] && runs+=("$out/level$k/bench.json"); done
else
  if [ ${#level3[@]} -gt 0 ]; then
    "$qc" bench "${level3[@]}" -o "$out/level3" --levels 3 --no-pictures "${flags[@]}" >&2
    runs+=("$out/level3/bench.json")
  fi
  if [ ${#level4[@]} -gt 0 ]; then
    "$qc" bench "${level4[@]}" -o "$out/level4" --levels 4 --no-pictures "${flags[@]}" >&2
    runs+=("$out/level4/bench.json")
  fi
  wall=$((SECONDS - start))
fi

python3 - "$check" "$wall" "$out" "${runs[@]}" -- "${meshes[@]}" <<'PY'
import json, os, statistics, subprocess, sys

check, wall, out = sys.argv[1] == "1", int(sys.argv[2]), sys.argv[3]
sep = sys.argv.index("--")
runs, meshes = sys.argv[4:sep], sys.argv[sep + 1:]
checker = "../shared/tools/check_fit.py"

rows = {}
for path in runs:
    run_dir = os.path.dirname(path)
    for m in json.load(open(path))["meshes"]:
        rows[os.path.abspath(m["file"])] = (run_dir, m)

def g(v, fmt="%.3g"):
    return "-" if v is None else fmt % v

def check_fit(mesh, surface):
    if not os.path.exists(surface):
        return "-", "-"
    try:
        # The checker's own interpreter (its #! line: Debian's python3 with numpy and scipy).
        text = subprocess.run([checker, "--input", mesh, "--surface", surface],
                              capture_output=True, text=True, check=True).stdout
        rel = json.loads([l for l in text.splitlines() if l.startswith("{")][-1])["relative"]
        return "%.3g" % rel["rms"], "%.3g" % rel["hausdorff"]
    except Exception as e:  # the checker failing must not hide the table
        return "error", type(e).__name__

head = ["mesh", "genus", "level", "control points ours / peer", "RMS ours", "RMS peer", "RMS ours/peer",
        "Hausdorff ours", "Hausdorff peer", "Hausdorff ours/peer", "peer status", "attempts",
        "fit s (ours: level K alone / peer)"]
if check:
    head += ["check_fit RMS ours / peer", "check_fit Hausdorff ours / peer"]
print("| " + " | ".join(head) + " |")
print("|" + "---|" * 3 + "---:|" * (len(head) - 3))
ratios, failures = [], []
for mesh in meshes:
    key = os.path.abspath(mesh)
    name = os.path.basename(mesh)
    if key not in rows:
        print("| %s |" % name + " - |" * 9 + " not run |" + " - |" * (len(head) - 11))
        continue
    run_dir, m = rows[key]
    if not m["levels"]:
        print("| %s | %s |" % (name, m["genus"] or "-") + " - |" * 8 + " ours: %s |" % m["status"] + " - |" * (len(head) - 11))
        continue
    lv = max(m["levels"], key=lambda l: l["level"])
    peer = next((p for p in m["peer"] if p["level"] == lv["level"]), {})
    note = peer.get("ratio_note") or "-"
    rr, hr = peer.get("rms_ratio"), peer.get("hausdorff_ratio")
    if rr is not None:
        ratios.append((rr, hr))
    cells = [name, m["genus"] or "-", str(lv["level"]),
             "%s / %s" % (g(lv["control_points"], "%d"), g(peer.get("control_points"), "%d")),
             g(lv["relative_rms"]), g(peer.get("relative_rms")), g(rr) if rr is not None else note,
             g(lv["relative_hausdorff"]), g(peer.get("relative_hausdorff")), g(hr) if hr is not None else note,
             peer.get("status", "-") if lv["status"] == "ok" else "ours: " + lv["status"],
             str(len(peer.get("attempts", []))),
             "%s / %s" % (g(lv["fit_seconds"], "%.1f"), g(peer.get("fit_seconds"), "%.1f"))]
    if check:
        folder = os.path.join(run_dir, m["folder"])
        ours = check_fit(mesh, os.path.join(folder, "level%d" % lv["level"], "limit.ply"))
        theirs = check_fit(mesh, os.path.join(folder, "peer", "level%d" % lv["level"], "fit", "limit.ply"))
        cells += ["%s / %s" % (ours[0], theirs[0]), "%s / %s" % (ours[1], theirs[1])]
    print("| " + " | ".join(cells) + " |")
    for a in peer.get("attempts", []):
        if a["outcome"] != "ok":
            failures.append("%s level %d: target %d faces, seed %d: %s%s" % (
                name, peer["level"], a["target_faces"], a["seed"], a["outcome"],
                "" if a["faces"] is None else " (%d faces)" % a["faces"]))
print()
if ratios:
    r, h = [x[0] for x in ratios], [x[1] for x in ratios]
    print("ours / peer over %d meshes at equal control points: RMS worst %.3g median %.3g; Hausdorff worst %.3g median %.3g"
          % (len(ratios), max(r), statistics.median(r), max(h), statistics.median(h)))
else:
    print("ours / peer: no mesh at equal control points")
if failures:
    print("\nQuadriFlow attempts not used as they were:")
    for f in failures:
        print("- " + f)
print("\n%sbench folders in %s" % ("" if wall < 0 else "wall %d s (both bench runs); " % wall, out))
PY
