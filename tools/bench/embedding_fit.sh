#!/usr/bin/env bash
# What the global embedding stage (issue #20) does to the fit: per mesh, `quadcage fit` at the
# issue's level (3; 4 for genus 0 and 1) without and with `--embedding-iterations N
# --embedding-extract`, each measured by the independent checkers, and whether the stage kept its
# extracted layout: tools/bench/fit_compare.sh with those two variants (its table and its default
# meshes).
#   tools/bench/embedding_fit.sh [BUILD_DIR] [ITERATIONS (default 30)] [MESH...]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
iterations=${2:-30}
shift $(($# > 2 ? 2 : $#))
exec bash tools/bench/fit_compare.sh "$build" --variant "off=" \
  --variant "on=--embedding-iterations $iterations --embedding-extract" "$@"
