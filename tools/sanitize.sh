#!/usr/bin/env bash
# tools/sanitize.sh [--cli]   ASan + UBSan build (build-sanitize/, clang; shared with tools/fuzz.sh)
# and run of the tests of
#   core   (I/O readers and writers, validation, output directories, generated shapes),
#   subdiv (cage refinement, Catmull-Clark, limit surface; OpenSubdiv);
# with --cli also the quadcage executable and the CLI tests (argument handling, info on every
# shared mesh, hostile inputs, output directories). --cli compiles every module with the sanitizers
# (well over ten minutes on 2 cores from scratch), so `tools/dev.sh test` (CI) runs the default only.
# Any sanitizer report fails the run (-fno-sanitize-recover, halt_on_error).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${QUADCAGE_SANITIZE_BUILD:-build-sanitize}
jobs=$(nproc 2>/dev/null || echo 2)
targets=(core_tests subdiv_tests)
case "${1:-}" in
  "") ;;
  --cli) targets+=(cli_tests) ;;
  *) echo "usage: tools/sanitize.sh [--cli]" >&2; exit 2 ;;
esac
bash tools/configure_sanitized.sh "$build"
for t in "${targets[@]}"; do cmake --build "$build" -j"$jobs" --target "$t"; done

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
labels=$(IFS='|'; echo "${targets[*]}")
ctest --test-dir "$build" --output-on-failure -j"$jobs" --timeout 900 -L "^($labels)\$"
