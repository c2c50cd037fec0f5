#!/usr/bin/env bash
# Scale of distributed builds (docs/distributed.md), measured, not tested: graphs/distributed_hydrology.json
# (fBm and basins; fill in both modes, D8 direction, D8 and MFD accumulation, watersheds, lakes) at
# RESOLUTION^2, built untiled in one process, then as TILES tiles on R = 1, 2, 4 ranks. Prints the wall time
# of each job and the peak resident memory of every rank (GNU time's %M).
#
# GRAPH=bench/distributed_fill.json measures the nodes that run across the tiles today (filling flat, lakes,
# normalization), GRAPH=bench/distributed_flow.json the flow nodes (epsilon fill, D8 direction, D8 accumulation with
# its flow map and wetness index): there each rank holds only its tiles.
# GRAPH=bench/scale_hydrology.json measures the whole hydrology core across the tiles (fill, D8 and MFD accumulation,
# rivers, watersheds) for the scale table.
# GRAPH=bench/distributed_mfd.json measures MFD FlowAccumulation across the tiles (the epsilon fill, the ring, the
# shares' rounds) with its flow map and wetness index.
# GRAPH=bench/distributed_thermal.json measures ThermalErosion across the tiles (halos exchanged every k
# iterations). GRAPH=bench/distributed_particles.json measures HydraulicErosion across the tiles (a round per droplet
# phase); its density is low for the tests: ARGS='--set droplets.droplets_per_km2=20000' gives two droplets a sample at
# 1025^2. ARGS (split on spaces) goes to every orogen eval.
# GRAPH=bench/distributed_pipe.json measures PipeErosion across the tiles (a 2-sample halo and a reduction every time
# step).
#
# Usage: [GRAPH=G.json] bench/bench_distributed.sh [ORGEN_BINARY] [RESOLUTION] [TILES] [RANKS...]
#   bench/bench_distributed.sh build/release/cli/orogen 2049 4x4 1 2 4
set -euo pipefail
orogen=${1:-build/release/cli/orogen}
res=${2:-2049}
tiles=${3:-4x4}
shift $(($# < 3 ? $# : 3))
ranks=("$@")
[ ${#ranks[@]} -gt 0 ] || ranks=(1 2 4)
graph=${GRAPH:-$(dirname "$0")/../graphs/distributed_hydrology.json}
read -r -a extra <<<"${ARGS:-}"
# Root and more ranks than cores (docs/distributed.md).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

run() {  # label, command...: wall seconds and the peak RSS of each process
  local label=$1
  shift
  local t0 t1
  t0=$(date +%s.%N)
  "$@" 2>"$out/err" >/dev/null || { cat "$out/err" >&2; exit 1; }
  t1=$(date +%s.%N)
  local peaks
  peaks=$(grep -o 'peak-kB [0-9]*' "$out/err" | awk '{printf "%s%.0f", (NR > 1 ? " " : ""), $2 / 1024}')
  printf '%-28s %8.2f s   peak MiB per rank: %s\n' "$label" "$(echo "$t1 - $t0" | bc)" "$peaks"
}

echo "$(basename "$graph") at ${res}x${res} ($(nproc) cores)"
run "untiled, 1 process" /usr/bin/time -f 'peak-kB %M' "$orogen" eval "$graph" --resolution "$res" -o "$out/a" -q \
  ${extra[@]+"${extra[@]}"}
for r in "${ranks[@]}"; do
  rm -rf "$out/b"
  run "--tiles $tiles on $r ranks" mpirun -n "$r" /usr/bin/time -f 'peak-kB %M' "$orogen" eval "$graph" \
    --resolution "$res" --tiles "$tiles" -o "$out/b" -q ${extra[@]+"${extra[@]}"}
done
