// Checks the MPI RankGroup (cli/mpi_rank_group.cpp) on however many ranks it is launched with: every collective
// returns what each rank sent, in rank order, and gather_by_tile orders parts by tile whichever rank gave them.
// Run by tests/test_distributed.cpp under mpirun; exits 0 when every rank agrees, 1 otherwise.
#include <cstdio>
#include <string>

#include "cli/mpi_rank_group.h"

int main() {
  std::string error;
  auto group = orogen::cli::start_rank_group(error);
  if (!group) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 2;
  }
  const int rank = group->rank(), ranks = group->size();
  bool ok = ranks > 1;

  const auto all = group->all_gather(std::string(static_cast<std::size_t>(rank), 'x') + std::to_string(rank));
  ok = ok && static_cast<int>(all.size()) == ranks;
  for (int r = 0; ok && r < ranks; ++r)
    ok = all[r] == std::string(static_cast<std::size_t>(r), 'x') + std::to_string(r);

  std::string message = rank == ranks - 1 ? std::string(100000, 'b') : "";
  group->broadcast(message, ranks - 1);
  ok = ok && message == std::string(100000, 'b');

  // Rank r sends "r->k" to every rank k but itself (nothing to itself).
  std::vector<std::string> outgoing(static_cast<std::size_t>(ranks));
  for (int k = 0; k < ranks; ++k)
    if (k != rank) outgoing[k] = std::to_string(rank) + "->" + std::to_string(k);
  const auto incoming = group->exchange(outgoing);
  for (int k = 0; ok && k < ranks; ++k)
    ok = incoming[k] == (k == rank ? std::string() : std::to_string(k) + "->" + std::to_string(rank));

  // Tiles given in reverse rank order come back sorted by tile; two parts of one tile keep their order.
  const std::int64_t tile = ranks - 1 - rank;
  const auto parts = gather_by_tile(*group, {{tile, "a" + std::to_string(tile)}, {tile, "b" + std::to_string(tile)}});
  ok = ok && static_cast<int>(parts.size()) == 2 * ranks;
  for (int k = 0; ok && k < 2 * ranks; ++k)
    ok = parts[k].tile == k / 2 && parts[k].bytes == (k % 2 ? "b" : "a") + std::to_string(k / 2);

  ok = ok && orogen::any_rank(*group, rank == ranks - 1) && !orogen::any_rank(*group, false);
  group->barrier();
  if (!ok) std::fprintf(stderr, "rank %d of %d: a collective returned the wrong bytes\n", rank, ranks);
  return ok ? 0 : 1;
}
