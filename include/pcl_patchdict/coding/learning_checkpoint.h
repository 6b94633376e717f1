// LearningCheckpoint — everything a streamed online-learning run needs to continue bit for bit
// (learner, shuffle buffer, position in the inputs); its binary .pdk file is io/learning_checkpoint_io.h.
#pragma once

#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/coding/patch_shuffle_buffer.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Where one shard of a sharded run (`learn --shards S`, or S MPI ranks) stood at a round's
  * end: its position in its own inputs, its shuffle buffer, the sub-batches it had made but not
  * yet handed over (a flush makes several at once), and its counters. */
struct ShardProgress {
  std::uint64_t begun = 0;         ///< of the shard's inputs, how many this pass has begun
  std::uint64_t next_column = 0;   ///< next patch of the input begun last, if it is still streaming
  bool streaming = false;          ///< that input has patches left (a resumed run reads it again)
  bool flushed = false;            ///< the pass's inputs are all in and the buffer flushed
  std::int32_t grid_size = 0;      ///< of the shard's patches so far (0: none yet)
  std::uint64_t patches = 0, patches_streamed = 0, patches_coded = 0, max_input_patches = 0;
  double observed_sum = 0.0;
  std::vector<std::pair<std::uint64_t, std::string>> skipped;  ///< input index, reason
  PatchShuffleBuffer::State buffer;
  std::vector<Eigen::MatrixXd> ready;        ///< sub-batches made, not yet handed over
  std::vector<ObservationMask> ready_masks;  ///< theirs (empty: all observed)
};

/** \brief The state of `learn --method online` between two inputs (one shard), or at a round's
  * end (several shards). `settings` are the named parameters that shape the result (atoms, seed,
  * grid, shards, …, as the caller writes them); with `inputs_fingerprint` they let a resumed run
  * refuse to continue a different job.
  *
  * Several shards or MPI ranks share one learner (Mairal et al. 2009's statistics are sums): each
  * codes its part of a round against the common dictionary and the summed statistics give every
  * holder the step one learner takes on the combined batch (OnlineDictionaryLearner::codeShard /
  * applyRound; docs/design.md, "Across machines"). Their checkpoint holds the common learner and
  * every shard's progress (`shards`).
  *
  * Its file (.pdk, io/learning_checkpoint_io.h; little-endian): magic "PCLPDK\0\x1a", version, then the fields below in
  * order (strings and matrices with their sizes first), then FNV-1a 64 of everything before it. */
struct LearningCheckpoint {
  std::vector<std::pair<std::string, std::string>> settings;
  std::uint64_t inputs_fingerprint = 0;
  std::uint64_t num_inputs = 0;

  std::uint32_t pass = 0;        ///< the pass in progress (== passes when the run is complete)
  std::uint64_t next_input = 0;  ///< index of the next input to stream in that pass
  std::int32_t grid_size = 0;    ///< of the patches seen so far (0: none yet)
  std::uint64_t patches = 0;     ///< distinct patches (first pass)
  std::uint64_t patches_streamed = 0;
  double observed_sum = 0.0;  ///< Σ over first-pass patches of their observed fraction
  std::vector<std::pair<std::uint64_t, std::string>> skipped;  ///< input index, reason

  OnlineDictionaryLearner::State learner;
  PatchShuffleBuffer::State buffer;
  /** A sharded run's shards (then `buffer`, `next_input` and the counters above are unused; the
    * learner is common); empty for a one-shard run. Version 2 of the format; version 1 files
    * (before shards) are read with none. */
  std::vector<ShardProgress> shards;
};

}  // namespace patchdict
}  // namespace pcl
