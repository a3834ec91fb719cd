// The processes of a study run under mpirun (`mpirun -n K kiln order ...`): each rank runs a share
// of the study's independent runs and every rank receives every result, so all ranks take the
// same decisions (a sweep's bisection, a failed reference) and build the same JSON, which rank 0
// alone writes. MPI (OpenMPI's C API) is started only when the process was launched by mpirun and
// only for a study; otherwise this is one rank, 0 of 1, and MPI is never touched.
//
// Errors never hang the job: a rank that fails outside the exchanges still takes part in the next
// one (from finish_ranks), where the others learn of it (RankFailed) and stop too.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace kiln {

// Starts MPI when this process was launched by mpirun (OpenMPI's OMPI_COMM_WORLD_SIZE or a PMIx
// launcher's PMIX_RANK in the environment); does nothing otherwise, and nothing the second time.
void start_ranks();

int this_rank();   // 0 without MPI
int rank_count();  // 1 without MPI

// Every rank's `mine`, in rank order, on every rank (a copy of `mine` alone without MPI). Throws
// RankFailed, on every rank that got here, when some rank has ended with an error instead; no
// further exchange is possible then.
std::vector<std::string> gather_on_every_rank(const std::string& mine);

// Another rank failed (its error is reported by finish_ranks on rank 0).
class RankFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Ends the process's part and returns its exit status. Without MPI: prints `error` (a full line,
// or "" for none) to standard error and returns `status`. Under MPI every rank learns every rank's
// outcome, here or in the exchange that threw RankFailed (then this rank's `status` and `error`,
// its reaction to another's failure, are not reported); rank 0 prints each different error once,
// naming the rank unless it is its own; MPI is finalised; and every rank returns the same status,
// the first failed rank's (in rank order), or 0.
int finish_ranks(int status, const std::string& error);

}  // namespace kiln
