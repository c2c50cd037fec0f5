#!/usr/bin/env bash
# Memory and CPU of tiled builds against the untiled one (docs/architecture.md, "Tiled builds"), measured, not
# tested: GRAPH at RESOLUTION^2 built untiled and with --tiles TILES by each binary given, REPS times,
# interleaved (binary A untiled, A tiled, B untiled, B tiled, then again), so that a busy machine weighs on
# every build alike. Prints each build's peak resident memory (GNU time's %M) and CPU time (perf's task-clock,
# every thread, user and system), then the medians.
#
# Usage: bench/bench_tile_memory.sh GRAPH RESOLUTION TILES REPS OROGEN_BINARY...
#   bench/bench_tile_memory.sh bench/tiled_local.json 4097 4x4 3 /tmp/old/bin/orogen build/release/cli/orogen
# A copied binary finds its image codec in ../lib/orogen beside it (or set OROGEN_IMAGE_CODEC).
set -euo pipefail
graph=$1 res=$2 tiles=$3 reps=$4
shift 4
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
declare -A rss cpu
run() {  # key, binary, extra arguments...
  local key=$1 bin=$2
  shift 2
  rm -rf "$out/o"
  perf stat -e task-clock -x, -o "$out/perf" /usr/bin/time -f 'peak-kB %M' -o "$out/time" \
    "$bin" eval "$graph" --resolution "$res" -o "$out/o" -q "$@" 2>"$out/err" >/dev/null ||
    { cat "$out/err" >&2; exit 1; }
  local kb ms
  kb=$(awk '/peak-kB/ {print $2}' "$out/time")
  ms=$(awk -F, '/task-clock/ {print $1}' "$out/perf")
  printf '%-10s %-40s %8.0f MiB %8.2f s CPU\n' "${key%%|*}" "$bin" "$((kb / 1024))" "$(echo "$ms / 1000" | bc -l)"
  rss[$key]+="$((kb / 1024)) "
  cpu[$key]+="$(echo "$ms / 1000" | bc -l) "
}
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
echo "$(basename "$graph") at ${res}^2, untiled and --tiles $tiles, $reps interleaved runs ($(nproc) cores)"
for ((r = 0; r < reps; ++r)); do
  for bin in "$@"; do
    run "untiled|$bin" "$bin"
    run "$tiles|$bin" "$bin" --tiles "$tiles"
  done
done
echo "medians:"
for bin in "$@"; do
  for mode in untiled "$tiles"; do
    key="$mode|$bin"
    printf '%-10s %-40s %8s MiB %8.2f s CPU\n' "$mode" "$bin" "$(echo "${rss[$key]}" | median)" \
      "$(echo "${cpu[$key]}" | median)"
  done
done
