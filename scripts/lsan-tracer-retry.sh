#!/usr/bin/env bash
# Reruns, once, the failed tests of a finished ctest run (build dir $1) when every one of them failed only
# because LeakSanitizer's exit-time tracer crashed (google/sanitizers#1353: "Tracer caught signal 11", then
# "LeakSanitizer has encountered a fatal error"): a crash of the sanitizer runtime, not a leak report. Exits 1
# if any failed test shows no such crash, or if a rerun fails again.
set -euo pipefail
build=$1
failed=$build/Testing/Temporary/LastTestsFailed.log
log=$build/Testing/Temporary/LastTest.log
[[ -s $failed && -s $log ]] || { echo "lsan-tracer-retry: no record of failed tests in $build" >&2; exit 1; }
count=0
while IFS= read -r line; do
  name=${line#*:}  # "<number>:<test name>"
  # The test's output in LastTest.log runs from its "N/M Test: <name>" line to its "Test Failed." line.
  output=$(awk -v n="$name" '
    /^[0-9]+\/[0-9]+ Test: / && substr($0, index($0, " Test: ") + 7) == n { on = 1 }
    on { print }
    on && /^Test (Failed|Passed)/ { exit }' "$log")
  if ! grep -q "Tracer caught signal" <<<"$output" ||
     ! grep -q "LeakSanitizer has encountered a fatal error" <<<"$output"; then
    echo "lsan-tracer-retry: $name failed for another reason; not retried" >&2
    exit 1
  fi
  echo "lsan-tracer-retry: LeakSanitizer's tracer crashed in $name"
  count=$((count + 1))
done <"$failed"
echo "lsan-tracer-retry: running the $count test(s) once more"
ctest --test-dir "$build" --output-on-failure --rerun-failed
