// MPI ranks of a `learn` run, or one process (learn_ranks.h). Only this file includes mpi.h.
#include "learn_ranks.h"

#include <pcl_patchdict/core/error.h>

#include <climits>
#include <cstdlib>
#include <exception>

#ifdef PCL_PATCHDICT_WITH_MPI
#include <mpi.h>
#endif

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

int launchedSize()
{
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* value = std::getenv(name))
      return std::atoi(value);
  return 1;
}

#ifdef PCL_PATCHDICT_WITH_MPI
int checkedCount(std::size_t count)
{
  if (count > static_cast<std::size_t>(INT_MAX))
    throw Error("MPI: a message of " + std::to_string(count) + " values is beyond MPI's int counts");
  return static_cast<int>(count);
}
#endif

#ifdef PCL_PATCHDICT_WITH_MPI
MPI_Datatype mpiType(const std::int64_t*) { return MPI_INT64_T; }
MPI_Datatype mpiType(const double*) { return MPI_DOUBLE; }
#endif

/** Every rank's `mine` (the same length on every rank), concatenated in rank order. */
template <typename T>
std::vector<T> allGatherSameLength(const std::vector<T>& mine, int size)
{
  if (size == 1)
    return mine;
  std::vector<T> all(mine.size() * static_cast<std::size_t>(size));
#ifdef PCL_PATCHDICT_WITH_MPI
  const int n = checkedCount(mine.size());
  MPI_Allgather(mine.data(), n, mpiType(mine.data()), all.data(), n, mpiType(mine.data()), MPI_COMM_WORLD);
#endif
  return all;
}

}  // namespace

bool Ranks::built()
{
#ifdef PCL_PATCHDICT_WITH_MPI
  return true;
#else
  return false;
#endif
}

bool Ranks::launchedAsMany()
{
  return launchedSize() > 1;
}

Ranks& Ranks::world()
{
  static Ranks ranks;
  return ranks;
}

Ranks::Ranks()
{
#ifdef PCL_PATCHDICT_WITH_MPI
  if (!launchedAsMany())
    return;
  int provided = 0;
  // Only the main thread calls MPI; OpenMP threads code in between.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  mpi_ = true;
  if (provided < MPI_THREAD_FUNNELED)  // every rank alike: the message is rank 0's
    fail("this MPI library does not allow threads beside the one calling MPI (MPI_THREAD_FUNNELED), which learn's "
         "OpenMP threads need: use an MPI built with thread support");
#endif
}

void Ranks::finish()
{
#ifdef PCL_PATCHDICT_WITH_MPI
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (mpi_ && !finalized)
    MPI_Finalize();
#endif
  mpi_ = false;
}

void Ranks::abortAll()
{
#ifdef PCL_PATCHDICT_WITH_MPI
  if (mpi_ && size_ > 1)
    MPI_Abort(MPI_COMM_WORLD, 1);
#endif
}

void Ranks::sum(double* data, std::size_t count) const
{
  if (size_ == 1)
    return;
#ifdef PCL_PATCHDICT_WITH_MPI
  const int n = checkedCount(count);
  std::vector<double> received(count);
  for (int step = 1; step < size_; step *= 2) {
    if (rank_ % (2 * step) == step) {  // hands its partial sum down and is done
      MPI_Send(data, n, MPI_DOUBLE, rank_ - step, 0, MPI_COMM_WORLD);
      break;
    }
    if (rank_ + step < size_) {
      MPI_Recv(received.data(), n, MPI_DOUBLE, rank_ + step, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      for (std::size_t i = 0; i < count; ++i)
        data[i] += received[i];
    }
  }
  MPI_Bcast(data, n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
#else
  (void)data;
  (void)count;
#endif
}

void Ranks::checkLengths(const std::vector<std::int64_t>& lengths) const
{
  for (const std::int64_t length : lengths)
    if (length > static_cast<std::int64_t>(INT_MAX))
      fail("a message of " + std::to_string(length) + " bytes between ranks is beyond MPI's int counts (a smaller "
           "--buffer keeps the checkpoints' per-rank state under 2 GB)");
}

void Ranks::broadcast(double* data, std::size_t count, int root) const
{
  if (size_ == 1)
    return;
#ifdef PCL_PATCHDICT_WITH_MPI
  MPI_Bcast(data, checkedCount(count), MPI_DOUBLE, root, MPI_COMM_WORLD);
#else
  (void)data;
  (void)count;
  (void)root;
#endif
}

std::vector<std::int64_t> Ranks::allGather(const std::vector<std::int64_t>& mine) const
{
  return allGatherSameLength(mine, size_);
}

std::vector<double> Ranks::allGather(const std::vector<double>& mine) const
{
  return allGatherSameLength(mine, size_);
}

std::vector<std::string> Ranks::allGatherBytes(const std::string& mine) const
{
  if (size_ == 1)
    return {mine};
  const std::vector<std::int64_t> lengths = allGather(std::vector<std::int64_t>{static_cast<std::int64_t>(mine.size())});
  std::int64_t sum = 0;
  for (const std::int64_t length : lengths)
    sum += length;
  checkLengths({sum});
  std::vector<std::string> all(static_cast<std::size_t>(size_));
#ifdef PCL_PATCHDICT_WITH_MPI
  std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    offsets[r] = checkedCount(total);
    counts[r] = checkedCount(static_cast<std::size_t>(lengths[r]));
    total += static_cast<std::size_t>(lengths[r]);
  }
  std::string joined(total, '\0');
  MPI_Allgatherv(mine.data(), checkedCount(mine.size()), MPI_CHAR, joined.data(), counts.data(), offsets.data(),
                 MPI_CHAR, MPI_COMM_WORLD);
  for (std::size_t r = 0; r < all.size(); ++r)
    all[r] = joined.substr(static_cast<std::size_t>(offsets[r]), static_cast<std::size_t>(counts[r]));
#endif
  return all;
}

std::vector<std::string> Ranks::gatherBytes(const std::string& mine) const
{
  if (size_ == 1)
    return {mine};
  const std::vector<std::int64_t> lengths = allGather(std::vector<std::int64_t>{static_cast<std::int64_t>(mine.size())});
  checkLengths(lengths);
  std::vector<std::string> all;
#ifdef PCL_PATCHDICT_WITH_MPI
  if (rank_ != 0) {
    MPI_Send(mine.data(), checkedCount(mine.size()), MPI_CHAR, 0, 1, MPI_COMM_WORLD);
    return all;
  }
  all.push_back(mine);
  for (int r = 1; r < size_; ++r) {
    std::string bytes(static_cast<std::size_t>(lengths[static_cast<std::size_t>(r)]), '\0');
    MPI_Recv(bytes.data(), checkedCount(bytes.size()), MPI_CHAR, r, 1, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    all.push_back(std::move(bytes));
  }
#endif
  return all;
}

void Ranks::agree(const std::function<void()>& work) const
{
  if (size_ == 1) {
    work();
    return;
  }
  std::exception_ptr failure;
  try {
    work();
  } catch (...) {
    failure = std::current_exception();
  }
  const std::vector<std::int64_t> failed = allGather(std::vector<std::int64_t>{failure ? 1 : 0});
  for (int r = 0; r < size_; ++r) {
    if (failed[static_cast<std::size_t>(r)] == 0)
      continue;
    stopped_together_ = true;
    if (r == rank_)
      std::rethrow_exception(failure);
    throw StoppedByAnotherRank();
  }
}

void Ranks::fail(const std::string& message) const
{
  stopped_together_ = true;
  if (rank_ == 0)
    throw Error(message);
  throw StoppedByAnotherRank();
}

void treeSum(std::vector<std::vector<double>>& parts)
{
  for (std::size_t step = 1; step < parts.size(); step *= 2)
    for (std::size_t s = 0; s + step < parts.size(); s += 2 * step)
      for (std::size_t i = 0; i < parts[s].size(); ++i)
        parts[s][i] += parts[s + step][i];
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
