// Online learning split into shards (MPI ranks, or shards of one process): each shard streams its
// inputs through its own shuffle buffer, and every mini-batch round sums the shards' statistics.
#pragma once

#include "learn_ranks.h"
#include "surface_patches.h"

#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/coding/learning_checkpoint.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** What a sharded run is asked to do. The inputs are dealt to the shards by size (largest file
  * first to the shard with the fewest bytes so far), each shard streams its own in list order
  * through a shuffle buffer of `buffer_capacity` patches seeded for s (shard 0 as a one-shard run), into
  * sub-batches of ⌊B/S⌋ patches (one more for the first B mod S shards): a round's combined batch
  * has B patches while every shard has some. */
struct ShardedLearningJob {
  std::vector<std::string> paths;
  int shards = 1;
  int passes = 3;
  std::size_t buffer_capacity = 20000;
  bool skip_bad = false;
  bool patch_cache = true;
  bool quiet = false;
  SurfacePatchOptions surface_options;
  int grid_size = 0;  ///< imposed (--grid), or 0: each shard's first input's
  OnlineLearningParameters parameters;
  /** Checkpoints (rank 0 writes them): at the end of the first round after every
    * `checkpoint_every` inputs begun (over all shards), at a stop, and at the end. `checkpoint`
    * holds the settings, fingerprint and input count to record; `stop_after` > 0 stops at the end
    * of the first round after that many inputs were begun in this run. */
  std::string checkpoint_path;
  std::size_t checkpoint_every = 0, stop_after = 0;
  LearningCheckpoint checkpoint;
  /** A sharded checkpoint to continue from (its shards the job's), or null. */
  const LearningCheckpoint* resume = nullptr;
};

/** What it made: the same on every rank. */
struct ShardedLearningResult {
  Eigen::MatrixXd dictionary;
  int grid_size = 0;
  std::uint64_t patches = 0;           ///< distinct patches (first pass)
  std::uint64_t patches_streamed = 0;  ///< over all passes
  double observed_sum = 0.0;           ///< Σ over first-pass patches of their observed fraction
  std::vector<std::pair<std::uint64_t, std::string>> skipped;  ///< input index, reason (ascending)
  std::vector<std::uint64_t> patches_coded;                    ///< per shard, over all passes
  std::size_t max_input_patches = 0, max_buffered = 0, cache_reads = 0;
  std::uint64_t cache_bytes = 0;
  bool complete = true;                ///< false: stopped (stop_after), resumable
  std::size_t checkpoints_written = 0;
  std::size_t steps = 0;               ///< the learner's rounds, earlier runs of a resumed job included
  std::size_t inputs_begun = 0;        ///< in this run, over all shards
  /** Rank 0's wall time in the parts of the rounds (the cost model in docs/results.md, "Learning
    * on several ranks"): its shards' reading and buffering, their coding (codeShard), the
    * exchanges of sizes and sums, and the atom update. Waiting for a slower rank falls in the
    * reading and the coding, whose ends every rank agrees on (Ranks::agree). */
  double seconds_read = 0.0, seconds_code = 0.0, seconds_exchange = 0.0, seconds_update = 0.0;
};

/** \brief Mini-batch rounds over S shards: each shard's sub-batch is coded against the common
  * dictionary (OnlineDictionaryLearner::codeShard), the statistics summed in a fixed binary tree
  * over shard indices (treeSum / Ranks::sum) and one update taken (applyRound) by every holder of
  * the learner. The first round's combined signals initialise the atoms, an unused atom restarts
  * from a column of the round's combined batch — so the dictionary is that of one learner fed the
  * combined batches, and the same bits whether the S shards run in one process or on S ranks.
  * With MPI, `ranks.size()` must equal `job.shards` (rank r runs shard r); in one process every
  * shard runs here. A bad input (without skip_bad) stops every rank at the next round with one
  * error line, from the rank that read it. */
ShardedLearningResult learnSharded(const ShardedLearningJob& job, const Ranks& ranks);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
