#!/usr/bin/env bash
# Scratch benchmark of the fit alone (until `quadcage fit` has real layouts): fit_bench on generated
# tori with their hand-built 4-quad layout, at the sizes of botijo (82k triangles) and botijo refined
# twice (1.3M), fitting level 3 (level mode), writing all outputs; prints errors, seconds by stage
# and peak memory.
#   tools/bench/fit_alone.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
bench="$build/fit_bench"
[ -x "$bench" ] || { echo "build first: $bench not found" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# torus(n, n/2) has n^2 triangles.
for n in 288 1140; do  # n and n/2 even (torus_layout)
  echo "== torus $n x $((n / 2)) ($((n * n)) triangles), level 3"
  FIT_BENCH_LEVEL=1 /usr/bin/time -f "peak %M KiB, wall %e s" "$bench" torus "$n" 3 0 "$work/out_$n" 2>&1 | tail -4
done
