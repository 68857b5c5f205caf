#!/usr/bin/env bash
# Meshes the project does not have, fitted as a new user would (`quadcage fit`, level 3; level 4
# for genus 0 and 1) and checked from outside: ../shared/tools/check_layout.py --quality and
# check_fit.py, and with --split also check_fit.py against each mesh with its long edges split
# (tools/bench/split_long_edges.py; the checker's nearest-centroid search misjudges long, thin
# triangles), in brackets. A mesh `quadcage info` rejects gets a row with its reason. Issue 20's
# targets on every row: area max/min <= 4, corner angle deviation <= 20 deg, RMS <= 1e-3 and
# Hausdorff <= 1e-2. Reports; asserts nothing. Needs no network: bring the files.
#   tools/bench/meshes.sh [--split] [BUILD_DIR] MESH...
# e.g. the closed ones of github.com/alecjacobson/common-3d-test-models (README, Benchmarks).
set -euo pipefail
here=$(pwd)
cd "$(dirname "$0")/../.."
fine=
if [ "${1:-}" = --split ]; then fine=fine; shift; fi
build=${1:-build}
shift || true
[ $# -gt 0 ] || { sed -n '2,10p' "$0" >&2; exit 2; }
qc="$build/quadcage"
[ -x "$qc" ] || { echo "build first: $qc not found" >&2; exit 2; }
[ -x ../shared/tools/check_layout.py ] && [ -x ../shared/tools/check_fit.py ] ||
  { echo "needs ../shared/tools/check_layout.py and check_fit.py" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# shellcheck source=tools/bench/fit_check_row.sh
. tools/bench/fit_check_row.sh
fit_check_header
for mesh in "$@"; do
  case "$mesh" in /*) ;; *) mesh="$here/$mesh" ;; esac
  name=$(basename "${mesh%.*}")
  if ! "$qc" info "$mesh" >"$work/info" 2>&1; then
    printf '| %s | | | | | | | rejected: %s | | | | | |\n' "$name" "$(grep -m1 'error' "$work/info" | sed 's/^.*cannot be quadded: //' | cut -c1-120)"
    continue
  fi
  fit_check_row "$name" "$mesh" "" "$fine"
done
