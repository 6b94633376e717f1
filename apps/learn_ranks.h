// The processes of one `learn` run: MPI ranks when the tool was started by mpirun (and built
// with MPI), else one process. Collectives in a fixed order, so results do not depend on timing.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** Thrown on the ranks that stop because another rank met an error (which that rank reports):
  * main prints nothing for it and exits 1. */
struct StoppedByAnotherRank : std::runtime_error {
  StoppedByAnotherRank() : std::runtime_error("stopped: another rank met an error") {}
};

class Ranks {
public:
  /** This process's view of the run; MPI is initialised on first use when the environment says
    * an MPI launcher started more than one process (OMPI_COMM_WORLD_SIZE, PMI_SIZE, PMIX_SIZE). */
  static Ranks& world();
  /** True when the tool was built with MPI. */
  static bool built();
  /** True when a launcher asked for more than one process (whatever the build). */
  static bool launchedAsMany();

  int rank() const { return rank_; }
  int size() const { return size_; }

  /** Element-wise sum over the ranks, the result on every rank: rank r's values added to those of
    * rank r − step in a binary tree (step 1, 2, 4 …), so the bits depend only on the rank count,
    * the same order treeSum() uses for shards in one process. */
  void sum(double* data, std::size_t count) const;
  /** Rank `root`'s values, on every rank. */
  void broadcast(double* data, std::size_t count, int root) const;
  /** Every rank's vector (the same length on every rank), concatenated in rank order. */
  std::vector<std::int64_t> allGather(const std::vector<std::int64_t>& mine) const;
  std::vector<double> allGather(const std::vector<double>& mine) const;
  /** Every rank's bytes, in rank order, on rank 0 (empty elsewhere). */
  std::vector<std::string> gatherBytes(const std::string& mine) const;
  /** Every rank's bytes, in rank order (lengths may differ). */
  std::vector<std::string> allGatherBytes(const std::string& mine) const;

  /** Runs `work`; then every rank learns whether any rank's work threw. If one did, the lowest
    * such rank rethrows its error (to be printed) and the others throw StoppedByAnotherRank; no
    * rank is left waiting. With one process, just `work()`. */
  void agree(const std::function<void()>& work) const;
  /** An error every rank meets alike (called by all): thrown by rank 0 to be printed, the others
    * stop quietly. */
  [[noreturn]] void fail(const std::string& message) const;
  /** True once agree() or fail() has stopped the run on every rank: an error reaching main
    * otherwise is this rank's alone, and only MPI_Abort frees the ranks waiting for it. */
  bool stoppedTogether() const { return stopped_together_; }

  /** Ends MPI (normal exit) or aborts every rank (an error only this rank met, outside agree()). */
  void finish();
  void abortAll();

private:
  Ranks();
  /** fail() on every rank alike when a length of an exchange is beyond MPI's int counts. */
  void checkLengths(const std::vector<std::int64_t>& lengths) const;
  int rank_ = 0;
  int size_ = 1;
  bool mpi_ = false;
  mutable bool stopped_together_ = false;
};

/** The binary-tree sum Ranks::sum() performs, over parts held in one process: parts[0] ends as
  * the sum, parts[s] += parts[s + step] for step 1, 2, 4 … */
void treeSum(std::vector<std::vector<double>>& parts);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
