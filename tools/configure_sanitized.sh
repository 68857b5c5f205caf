#!/usr/bin/env bash
# tools/configure_sanitized.sh [BUILD_DIR]   configure BUILD_DIR (default build-sanitize/) once: clang,
# ASan + UBSan (any report is fatal) and libFuzzer's coverage instrumentation, with the fuzz targets.
# Shared by tools/sanitize.sh (the core and subdiv tests) and tools/fuzz.sh (tests/fuzz), so that the
# libraries are compiled once for both.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-sanitize}
if ! command -v clang++ >/dev/null; then
  echo "$0: clang++ not found; install clang and libclang-rt-14-dev (tools/install_deps.sh)" >&2
  exit 2
fi
[ -f "$build/CMakeCache.txt" ] && exit 0
mkdir -p "$build"
flags="-O1 -gline-tables-only -fno-omit-frame-pointer -fsanitize=address,undefined,fuzzer-no-link"
flags+=" -fno-sanitize-recover=undefined"
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug -DQUADCAGE_BUILD_FUZZERS=ON \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  >"$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; rm -f "$build/CMakeCache.txt"; exit 1; }
