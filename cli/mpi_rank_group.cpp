#include "cli/mpi_rank_group.h"

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <stdexcept>

#ifdef OROGEN_HAVE_MPI
// The C API only: no C++ bindings (deprecated, and their symbols live in another library).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace orogen::cli {

namespace {

int env_int(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : 0;
}

#ifdef OROGEN_HAVE_MPI

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

int as_count(std::size_t n) {
  if (n > static_cast<std::size_t>(INT_MAX)) throw std::runtime_error("MPI: a message over 2 GiB");
  return static_cast<int>(n);
}

class MpiGroup final : public RankGroup {
 public:
  MpiGroup() {
    int provided = 0;
    // Only the main thread calls MPI; the evaluator's worker threads never do.
    check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
    MPI_Comm node = MPI_COMM_NULL;
    check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
          "MPI_Comm_split_type");
    check(MPI_Comm_size(node, &local_size_), "MPI_Comm_size");
    MPI_Comm_free(&node);
  }
  ~MpiGroup() override { MPI_Finalize(); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int local_size() const override { return local_size_; }

  std::vector<std::string> all_gather(const std::string& mine) override {
    int n = as_count(mine.size());
    std::vector<int> counts(size_), offsets(size_);
    check(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    const std::size_t total = offsets_of(counts, offsets);
    std::string all(total, '\0');
    check(MPI_Allgatherv(mine.data(), n, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    return split(all, counts, offsets);
  }

  void broadcast(std::string& bytes, int root) override {
    unsigned long long n = bytes.size();
    check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD), "MPI_Bcast");
    bytes.resize(static_cast<std::size_t>(n));
    check(MPI_Bcast(bytes.data(), as_count(bytes.size()), MPI_BYTE, root, MPI_COMM_WORLD), "MPI_Bcast");
  }

  std::vector<std::string> exchange(const std::vector<std::string>& outgoing) override {
    std::vector<int> send_counts(size_, 0), send_offsets(size_), recv_counts(size_), recv_offsets(size_);
    std::string sent;
    for (int r = 0; r < size_ && r < static_cast<int>(outgoing.size()); ++r) {
      send_counts[r] = as_count(outgoing[r].size());
      sent += outgoing[r];
    }
    offsets_of(send_counts, send_offsets);
    check(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Alltoall");
    std::string received(offsets_of(recv_counts, recv_offsets), '\0');
    check(MPI_Alltoallv(sent.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, received.data(),
                        recv_counts.data(), recv_offsets.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Alltoallv");
    return split(received, recv_counts, recv_offsets);
  }

  void barrier() override { check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier"); }

  [[noreturn]] void abort(int code) override {
    std::fflush(stdout);
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);  // MPI_Abort does not return; this is for implementations whose abort is lazy
  }

 private:
  // Exclusive prefix sums of `counts` into `offsets`; returns the total.
  static std::size_t offsets_of(const std::vector<int>& counts, std::vector<int>& offsets) {
    std::size_t total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      offsets[r] = as_count(total);
      total += static_cast<std::size_t>(counts[r]);
    }
    as_count(total);
    return total;
  }
  static std::vector<std::string> split(const std::string& all, const std::vector<int>& counts,
                                        const std::vector<int>& offsets) {
    std::vector<std::string> parts(counts.size());
    for (std::size_t r = 0; r < counts.size(); ++r) parts[r] = all.substr(offsets[r], counts[r]);
    return parts;
  }

  int rank_ = 0, size_ = 1, local_size_ = 1;
};

#endif

[[maybe_unused]] bool launched_by_mpi() {
  return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK") ||
         env_int("SLURM_STEP_NUM_TASKS") > 1;
}

}  // namespace

int launcher_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"})
    if (const int n = env_int(name); n > 0) return n;
  return 1;
}

std::unique_ptr<RankGroup> start_rank_group(std::string& error) {
#ifdef OROGEN_HAVE_MPI
  if (launched_by_mpi()) return std::make_unique<MpiGroup>();
#else
  if (launcher_ranks() > 1) {
    error = "launched on " + std::to_string(launcher_ranks()) +
            " ranks, but this orogen was built without MPI (OROGEN_MPI off): every rank would build the whole job; "
            "install libopenmpi-dev and rebuild, or run one process";
    return nullptr;
  }
#endif
  (void)error;
  return single_process_group();
}

}  // namespace orogen::cli
