#!/usr/bin/env bash
# Compare the outputs of two orogen builds, byte for byte, graph by graph: the check that a graph-format
# migration changed only names (docs/conventions.md, "Byte identity of the format-6 renames").
#
# Usage: scripts/compare-builds.sh OLD_OROGEN NEW_OROGEN OLD_GRAPH_DIR NEW_GRAPH_DIR [EVAL_ARGS...]
#
#   OLD_OROGEN, NEW_OROGEN        the two CLI binaries (e.g. build/release/cli/orogen of two worktrees)
#   OLD_GRAPH_DIR, NEW_GRAPH_DIR  the graph files each binary reads; graphs are paired by file name (*.json
#                                 present in both directories), so the old binary reads its own format
#   EVAL_ARGS                     passed to both `orogen eval` runs; default: --resolution 129 --threads 2
#
# Each graph is evaluated once per binary into a fresh output directory (no --cache-dir, so no persistent
# cache is shared); then every file either run wrote is compared with cmp. Prints one line per file:
#   identical GRAPH/FILE | different GRAPH/FILE | only-old GRAPH/FILE | only-new GRAPH/FILE
# a line per graph whose evaluation failed (eval-failed-old / eval-failed-new, with the log's path) or that
# the old directory lacks (skipped),
# then a summary. Exit status: 0 when every file is identical, 1 otherwise, 2 on a usage error.
# Environment: KEEP=1 keeps the output directories (their path is printed) for a closer look.
set -u

if [[ $# -lt 4 ]]; then
  sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
old_bin=$1 new_bin=$2 old_dir=$3 new_dir=$4
shift 4
eval_args=("$@")
[[ ${#eval_args[@]} -eq 0 ]] && eval_args=(--resolution 129 --threads 2)
for b in "$old_bin" "$new_bin"; do
  [[ -x $b ]] || { echo "not an executable: $b" >&2; exit 2; }
done
for d in "$old_dir" "$new_dir"; do
  [[ -d $d ]] || { echo "not a directory: $d" >&2; exit 2; }
done

work=$(mktemp -d "${TMPDIR:-/tmp}/compare-builds.XXXXXX")
[[ ${KEEP:-0} == 1 ]] || trap 'rm -rf "$work"' EXIT

graphs=0 files=0 identical=0 different=0 unpaired=0 failed=0
for new_graph in "$new_dir"/*.json; do
  name=$(basename "$new_graph" .json)
  old_graph="$old_dir/$name.json"
  [[ -f $old_graph ]] || { echo "skipped $name (no $old_graph)"; continue; }
  graphs=$((graphs + 1))
  ok=1
  for side in old new; do
    bin_var=${side}_bin graph_var=${side}_graph
    out="$work/$side/$name"
    mkdir -p "$out"
    if ! "${!bin_var}" eval "${!graph_var}" -o "$out" --quiet "${eval_args[@]}" >"$work/$side-$name.log" 2>&1; then
      echo "eval-failed-$side $name ($work/$side-$name.log)"
      failed=$((failed + 1)) ok=0
    fi
  done
  [[ $ok == 1 ]] || continue
  # Union of the relative paths both runs wrote, compared pairwise.
  while IFS= read -r rel; do
    files=$((files + 1))
    a="$work/old/$name/$rel" b="$work/new/$name/$rel"
    if [[ ! -e $a ]]; then
      echo "only-new $name/$rel"; unpaired=$((unpaired + 1))
    elif [[ ! -e $b ]]; then
      echo "only-old $name/$rel"; unpaired=$((unpaired + 1))
    elif cmp -s "$a" "$b"; then
      echo "identical $name/$rel"; identical=$((identical + 1))
    else
      echo "different $name/$rel"; different=$((different + 1))
    fi
  done < <( (cd "$work/old/$name" && find . -type f; cd "$work/new/$name" && find . -type f) | sed 's|^\./||' | sort -u)
done

echo "summary: $graphs graphs, $files files: $identical identical, $different different, $unpaired unpaired," \
  "$failed failed evaluations"
[[ ${KEEP:-0} == 1 ]] && echo "outputs kept in $work"
[[ $different == 0 && $unpaired == 0 && $failed == 0 ]]
