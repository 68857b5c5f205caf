#!/usr/bin/env bash
# The two quick-start commands of the README:
#   tools/dev.sh demo   install what is missing, build, fit a cage to the bundled mesh data/eight.off (-> out/eight)
#   tools/dev.sh test   install what is missing, build, run every test (ctest), then the ASan + UBSan
#                       build of the core and subdiv tests (tools/sanitize.sh) and a fuzz smoke
#                       run of every loader (tools/fuzz.sh, 60 s in all)
set -euo pipefail
cd "$(dirname "$0")/.."

what=${1:-}
case "$what" in demo|test) ;; *) echo "usage: tools/dev.sh demo|test" >&2; exit 2 ;; esac

bash tools/install_deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"

if [ "$what" = demo ]; then
  ./build/quadcage info data/eight.off
  ./build/quadcage fit data/eight.off -o out/eight   # layout (10 quads) + Catmull-Clark fit at level 3
  exit 0
fi

if [ ! -d ../shared/data/meshes ]; then
  echo "note: ../shared/data/meshes not found beside the checkout: tests on real meshes are skipped" >&2
fi
ctest --test-dir build --output-on-failure -j"$jobs" --timeout 900

t0=$(date +%s)
bash tools/sanitize.sh
t1=$(date +%s)
bash tools/fuzz.sh "${QUADCAGE_FUZZ_SECONDS:-60}"
t2=$(date +%s)
echo "dev.sh: sanitizer build and tests $((t1 - t0)) s, fuzz smoke $((t2 - t1)) s"
