#!/usr/bin/env bash
# tools/fuzz.sh [SECONDS]   fuzz every loader entry point for SECONDS in all (default 60), split evenly.
#
# Builds the libFuzzer targets of tests/fuzz (clang, ASan + UBSan) into build-sanitize/ if needed
# (tools/configure_sanitized.sh; tools/sanitize.sh shares it), makes the
# seed corpus (tools/fuzz_corpus.py) and runs each target with a per-input timeout, a memory cap and a
# maximum input size, so that slow or memory-hungry inputs count as findings too. The corpus grows in
# build-sanitize/fuzz/corpus/<target> from run to run; findings go to build-sanitize/fuzz/findings/<target>/
# (reproduce one with `build-sanitize/fuzz_<target> FILE`). Prints a summary; exits 1 on any finding.
# Environment: QUADCAGE_SANITIZE_BUILD (build directory), QUADCAGE_FUZZ_TIMEOUT (seconds per input, 5),
# QUADCAGE_FUZZ_RSS_MB (memory cap, 2048), QUADCAGE_FUZZ_MAX_LEN (bytes, 65536).
set -euo pipefail
cd "$(dirname "$0")/.."

total=${1:-60}
case "$total" in '' | *[!0-9]*) echo "usage: tools/fuzz.sh [SECONDS]" >&2; exit 2 ;; esac
build=${QUADCAGE_SANITIZE_BUILD:-build-sanitize}
timeout=${QUADCAGE_FUZZ_TIMEOUT:-5}
rss_mb=${QUADCAGE_FUZZ_RSS_MB:-2048}
max_len=${QUADCAGE_FUZZ_MAX_LEN:-65536}
targets=(obj ply off stl extras cage)
jobs=$(nproc 2>/dev/null || echo 2)

bash tools/configure_sanitized.sh "$build"
cmake --build "$build" -j"$jobs" --target "${targets[@]/#/fuzz_}" >/dev/null

work="$build/fuzz"
rm -rf "$work/seeds"
python3 tools/fuzz_corpus.py "$work/seeds" >/dev/null
per=$(( total / ${#targets[@]} ))
[ "$per" -ge 1 ] || per=1

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
failed=0
mkdir -p "$work"
touch "$work/.started"  # findings of this run are the files newer than this
for t in "${targets[@]}"; do
  mkdir -p "$work/corpus/$t" "$work/findings/$t" "$work/logs"
  log="$work/logs/$t.log"
  set +e
  "$build/fuzz_$t" -max_total_time="$per" -timeout="$timeout" -rss_limit_mb="$rss_mb" -max_len="$max_len" \
    -artifact_prefix="$work/findings/$t/" -print_final_stats=1 "$work/corpus/$t" "$work/seeds/$t" >"$log" 2>&1
  rc=$?
  set -e
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  corpus=$(find "$work/corpus/$t" -type f | wc -l)
  findings=$(find "$work/findings/$t" -type f -newer "$work/.started" | wc -l)
  if [ "$rc" -ne 0 ] && [ "$findings" -eq 0 ]; then findings=1; fi  # e.g. a crash before writing the input
  line=$(printf "fuzz_%-7s %4ss  runs %-10s corpus %-6s exit %-3s findings %s" "$t" "$per" "${runs:-?}" "$corpus" "$rc" "$findings")
  if [ "$findings" -ne 0 ]; then
    failed=1
    line+="  (see $log and $work/findings/$t/)"
  fi
  echo "$line"
done
echo "fuzz: ${#targets[@]} targets, $per s each: $([ $failed -eq 0 ] && echo 'no finding' || echo 'FINDINGS')"
exit $failed
