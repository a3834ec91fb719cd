#include "src/studies/study_ranks.h"

// The C API only: OpenMPI's mpi.h would otherwise bring in its deprecated C++ bindings.
#define OMPI_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "src/base/text_format.h"

namespace kiln {

namespace {

bool started = false;

// Each rank's block in an exchange: 'r' then its data, or 'e' then its exit status and error when
// it has failed instead (so the others learn of it in the exchange they are waiting in).
struct Outcome {
  int status = 0;
  std::string error;
};
bool settled = false;           // an exchange has shown a failure: no further exchange will happen
std::vector<Outcome> outcomes;  // then every rank's, as that exchange found it

std::string failure_block(int status, const std::string& error) {
  std::string block(1 + sizeof status, 'e');
  std::memcpy(block.data() + 1, &status, sizeof status);
  return block + error;
}

// Every rank's block on every rank, in rank order. MPI counts are ints (OpenMPI 4 has no
// large-count collectives): a rank whose block is larger fails alone, before the exchange, and
// the others learn of it in the exchange; a larger total fails on every rank alike.
std::vector<std::string> all_gather(const std::string& block) {
  if (block.size() > INT_MAX) throw std::length_error("a rank's study results exceed 2 GiB: too large to exchange");
  const int size = rank_count();
  const int mine = static_cast<int>(block.size());
  std::vector<int> sizes(size), offsets(size, 0);
  MPI_Allgather(&mine, 1, MPI_INT, sizes.data(), 1, MPI_INT, MPI_COMM_WORLD);
  long total = 0;
  for (int s : sizes) total += s;
  if (total > INT_MAX) throw std::length_error("the study's results exceed 2 GiB: too large to exchange");
  for (int r = 1; r < size; ++r) offsets[r] = offsets[r - 1] + sizes[r - 1];
  std::string all(static_cast<size_t>(total), '\0');
  MPI_Allgatherv(block.data(), mine, MPI_BYTE, all.data(), sizes.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD);
  std::vector<std::string> blocks;
  for (int r = 0; r < size; ++r) blocks.push_back(all.substr(offsets[r], sizes[r]));
  return blocks;
}

// Reads the outcomes of an exchange's blocks; true when some rank has failed.
bool any_failure(const std::vector<std::string>& blocks) {
  std::vector<Outcome> found(blocks.size());
  bool failed = false;
  for (size_t r = 0; r < blocks.size(); ++r) {
    if (blocks[r].front() != 'e') continue;
    std::memcpy(&found[r].status, blocks[r].data() + 1, sizeof found[r].status);
    found[r].error = blocks[r].substr(1 + sizeof found[r].status);
    failed = true;
  }
  if (failed) {
    settled = true;
    outcomes = found;
  }
  return failed;
}

}  // namespace

void start_ranks() {
  if (started || !(std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK"))) return;
  int provided = 0;
  // Funneled: the study's worker threads never call MPI, only the main thread does.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  started = true;
}

int this_rank() {
  int rank = 0;
  if (started) MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int rank_count() {
  int size = 1;
  if (started) MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

std::vector<std::string> gather_on_every_rank(const std::string& mine) {
  if (!started) return {mine};
  if (settled) throw RankFailed("a rank of the study has failed");
  std::vector<std::string> blocks = all_gather("r" + mine);
  if (any_failure(blocks)) throw RankFailed("a rank of the study has failed");
  for (std::string& b : blocks) b.erase(0, 1);
  return blocks;
}

int finish_ranks(int status, const std::string& message) {
  const std::string error = bounded(message);
  if (!started) {
    if (!error.empty()) std::fprintf(stderr, "%s\n", error.c_str());
    return status;
  }
  const int rank = this_rank(), size = rank_count();
  const bool failed = settled || any_failure(all_gather(status != 0 ? failure_block(status, error) : "r"));
  MPI_Finalize();
  if (!failed) return status;
  // Rank 0 says each different error once (every rank fails alike on a bad scene), naming the
  // rank unless it is its own; every rank exits with the first failed rank's status.
  if (rank == 0) {
    std::vector<std::string> said;
    for (int r = 0; r < size; ++r) {
      const std::string& e = outcomes[r].error;
      if (e.empty() || std::find(said.begin(), said.end(), e) != said.end()) continue;
      said.push_back(e);
      if (r == 0)
        std::fprintf(stderr, "%s\n", e.c_str());
      else
        std::fprintf(stderr, "rank %d of %d: %s\n", r, size, e.c_str());
    }
  }
  for (const Outcome& o : outcomes)
    if (o.status != 0) return o.status;
  return status;
}

}  // namespace kiln
