#pragma once
// The ranks of this `orogen` process: MPI_COMM_WORLD when a launcher started it (mpirun, mpiexec or srun, which
// set OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_RANK or SLURM_STEP_NUM_TASKS), else the single-process group. MPI is
// initialized here, only then, and finalized when the group is destroyed; standard MPI-3 calls only (Open MPI
// and MPICH). An orogen built without MPI (OROGEN_MPI off) and launched on several ranks refuses to run rather
// than have every rank build and write the whole job.
#include <memory>
#include <string>

#include "graph/rank_group.h"

namespace orogen::cli {

// The number of ranks the launcher's environment announces (1 when there is none).
int launcher_ranks();

// The group; nullptr and `error` set when the process cannot take part (launched on several ranks without MPI).
std::unique_ptr<RankGroup> start_rank_group(std::string& error);

}  // namespace orogen::cli
