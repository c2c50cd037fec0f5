#pragma once
// The processes of a distributed build (docs/distributed.md) and the exchanges between them, with no MPI in
// sight: the CLI implements RankGroup over MPI (cli/mpi_rank_group.cpp) when it is launched by mpirun or srun,
// and single_process_group() is the one-rank group of an ordinary build. Tiles are spread over the ranks
// (cli/tile_assignment.h); what one tile needs from another (a reduction's partial result, a halo, a perimeter
// of a tile-graph algorithm) travels as bytes through these collectives.
//
// Every call but rank(), size(), local_size() and abort() is collective: every rank of the group makes it, in
// the same order. Results never depend on which rank computed what: gather_by_tile() orders contributions by
// tile, so a reduction combined in that order gives the same bits for any rank count.
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace orogen {

class RankGroup {
 public:
  virtual ~RankGroup() = default;
  // This process's rank, from 0, and the number of ranks.
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Ranks on this machine (they share its cores and memory).
  virtual int local_size() const = 0;

  // Every rank's `mine`, indexed by rank, on every rank.
  virtual std::vector<std::string> all_gather(const std::string& mine) = 0;
  // `bytes` of rank `root` on every rank.
  virtual void broadcast(std::string& bytes, int root) = 0;
  // Point-to-point in one collective step: outgoing[r] goes to rank r (empty: nothing); returns what each rank
  // sent this one, indexed by sender. Halo exchange and perimeter graphs are built on it.
  virtual std::vector<std::string> exchange(const std::vector<std::string>& outgoing) = 0;
  virtual void barrier() = 0;
  // Ends every rank's process now with exit code `code` (not collective: the rank that failed calls it alone).
  [[noreturn]] virtual void abort(int code) = 0;
};

// The group of one process: rank 0 of 1, every collective a copy.
std::unique_ptr<RankGroup> single_process_group();

// One tile's contribution to a job-wide result: the tile's row-major index and its bytes.
struct TilePart {
  std::int64_t tile = 0;
  std::string bytes;
};
// Every rank's parts on every rank, sorted by tile (ties: in the order the owning rank gave them). Combining
// them in this order makes a reduction independent of the rank count and of the tile assignment.
std::vector<TilePart> gather_by_tile(RankGroup& group, const std::vector<TilePart>& mine);

// Whether `mine` is true on any rank (an agreement step: every rank learns the same answer).
bool any_rank(RankGroup& group, bool mine);

}  // namespace orogen
