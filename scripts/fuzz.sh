#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan + fuzzer coverage) in build/fuzz and runs each for a
# share of a fixed time budget (default 60 s in all), from the seed corpora: graphs/*.json, the subgraph
# library and tests/fuzz/graph_file_seeds for the graph reader, small images of each format for ReadHeightfield, parameter texts for the text grammars, and the
# L-system grammars of graphs/plants.json for LSystem, byte strings that decode to whole graphs of the newer
# families for the evaluation under a time and memory budget.
#   scripts/fuzz.sh [SECONDS]
# Exits 0 if clang cannot build a fuzzer here (reported; 1 instead when OROGEN_FUZZ_REQUIRED=1, as CI sets it),
# 1 if a target found a crash (the reproducer is in build/fuzz/artifacts/).
set -euo pipefail
cd "$(dirname "$0")/.."
total="${1:-60}"
export CCACHE_BASEDIR="$(pwd)"
CXX_FUZZ="${CXX_FUZZ:-$(command -v clang++-14 || command -v clang++ || true)}"
CC_FUZZ="${CC_FUZZ:-$(command -v clang-14 || command -v clang || true)}"
skip() { echo "fuzz.sh: $1"; [ "${OROGEN_FUZZ_REQUIRED:-0}" = 1 ] && exit 1; exit 0; }
if [ -z "$CXX_FUZZ" ]; then skip "no clang; skipped"; fi
probe="$(mktemp -d)"
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' > "$probe/p.cpp"
if ! "$CXX_FUZZ" -fsanitize=fuzzer,address "$probe/p.cpp" -o "$probe/p" 2>/dev/null; then
  rm -rf "$probe"; skip "$CXX_FUZZ cannot build a libFuzzer target here; skipped"
fi
rm -rf "$probe"

# -O1 with line tables only: instrumented code compiles about twice as fast as RelWithDebInfo and still
# fuzzes quickly; stack traces keep file and line.
cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" \
  -DCMAKE_C_FLAGS_DEBUG="-O1 -gline-tables-only" -DCMAKE_C_COMPILER="$CC_FUZZ" \
  -DCMAKE_CXX_COMPILER="$CXX_FUZZ" -DOROGEN_FUZZ=ON -DOROGEN_EDITOR=OFF -DOROGEN_BENCH=OFF -DOROGEN_TESTS=OFF
cmake --build build/fuzz -j"$(nproc)" --target orogen_fuzz_graph_file orogen_fuzz_heightfield_image \
  orogen_fuzz_param_text orogen_fuzz_lsystem orogen_fuzz_graph_eval

work=build/fuzz/run
mkdir -p "$work/graph" "$work/image" "$work/param" "$work/lsystem" "$work/eval" build/fuzz/artifacts
cp graphs/*.json "$work/graph/"
# Version 4: the string tables the migration converts (renamed so that today's graphs, some of which use
# subgraph instances, are kept beside them).
for f in tests/fixtures/v4/*.json; do cp "$f" "$work/graph/v4_$(basename "$f")"; done
cp graphs/library/*.json tests/fuzz/graph_file_seeds/*.json "$work/graph/"  # subgraph assets and instances
bash tests/fuzz/make_image_seeds.sh "$work/image"
cp tests/fuzz/param_seeds/* "$work/param/" 2>/dev/null || true
cp tests/fuzz/lsystem_seeds/* "$work/lsystem/"
cp tests/fuzz/graph_eval_seeds/* "$work/eval/"

export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
run() {  # target corpus seconds [extra args]
  local target="$1" corpus="$2" seconds="$3"; shift 3
  echo "== $target for ${seconds} s"
  "build/fuzz/tests/fuzz/$target" "$corpus" -max_total_time="$seconds" -rss_limit_mb=3072 -malloc_limit_mb=2048 \
    -timeout=20 -artifact_prefix=build/fuzz/artifacts/"$target"- -print_final_stats=1 "$@" 2>&1 | tail -n 12
  return "${PIPESTATUS[0]}"
}
quarter=$((total / 4)); eighth=$((total / 8))
run orogen_fuzz_graph_file "$work/graph" "$quarter" -dict=tests/fuzz/graph_file.dict
run orogen_fuzz_heightfield_image "$work/image" "$eighth"
run orogen_fuzz_param_text "$work/param" "$eighth" -dict=tests/fuzz/graph_file.dict
run orogen_fuzz_lsystem "$work/lsystem" "$eighth"
# Whole graphs: a graph's evaluation is cancelled after 0.3 s and must stop within 5 s (else it aborts); the
# cost model refuses nodes above 256 MB (an estimate may be 2x low), so memory far beyond that is an estimate
# that was wrong. Two limits, as libFuzzer defines them (later flags override run's): -malloc_limit_mb fails
# a single allocation of 1 GB or more at once; -rss_limit_mb fails the run when the process's resident memory,
# sampled about once a second, exceeds 1.5 GB (ASan's shadow and quarantine and the corpus take a few hundred
# MB of it), which catches many smaller allocations adding up.
run orogen_fuzz_graph_eval "$work/eval" "$((total - quarter - 3 * eighth))" -malloc_limit_mb=1024 -rss_limit_mb=1536
