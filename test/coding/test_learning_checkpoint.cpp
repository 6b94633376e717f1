// OnlineDictionaryLearner state, PatchShuffleBuffer and the .pdk checkpoint: saving mid-stream and
// continuing gives the same dictionary bit for bit; damaged files are refused; shards' statistics add.
#include <pcl_patchdict/coding/dictionary_learning.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/learning_checkpoint.h>
#include <pcl_patchdict/coding/patch_shuffle_buffer.h>
#include <pcl_patchdict/io/learning_checkpoint_io.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

using namespace pcl::patchdict;

namespace {

Eigen::MatrixXd randomSignals(int rows, int cols, std::uint64_t seed)
{
  return test_support::gaussianMatrix(rows, cols, seed);
}

ObservationMask someHidden(int rows, int cols)
{
  ObservationMask mask = ObservationMask::Constant(rows, cols, true);
  for (int p = 0; p < cols; p += 3)
    mask(p % rows, p) = false;
  return mask;
}

}  // namespace

TEST(LearningCheckpoint, StoppedAndResumedStreamGivesTheSameDictionary)
{
  const OnlineLearningParameters parameters{10, 3, 16, 5};
  std::vector<Eigen::MatrixXd> parts;
  for (int i = 0; i < 5; ++i)
    parts.push_back(randomSignals(25, 70 + 10 * i, 100 + static_cast<std::uint64_t>(i)));
  const ObservationMask mask = someHidden(25, 90);

  // Uninterrupted.
  OnlineDictionaryLearner whole(parameters);
  PatchShuffleBuffer whole_buffer(60, parameters.batch_size, parameters.seed);
  for (const auto& part : parts)
    whole_buffer.add(part, part.cols() == 90 ? mask : ObservationMask(), whole);
  whole_buffer.flush(whole);
  EXPECT_EQ(whole_buffer.highWater(), 60u);
  EXPECT_EQ(whole.signalsSeen(), 450u);

  // Stopped after three parts, saved as bytes, loaded into fresh objects, continued.
  std::string bytes;
  {
    OnlineDictionaryLearner learner(parameters);
    PatchShuffleBuffer buffer(60, parameters.batch_size, parameters.seed);
    for (int i = 0; i < 3; ++i)
      buffer.add(parts[static_cast<std::size_t>(i)], parts[static_cast<std::size_t>(i)].cols() == 90 ? mask : ObservationMask(), learner);
    ASSERT_GT(buffer.size(), 0u);
    LearningCheckpoint checkpoint;
    checkpoint.settings = {{"atoms", "10"}};
    checkpoint.next_input = 3;
    checkpoint.num_inputs = 5;
    checkpoint.learner = learner.state();
    checkpoint.buffer = buffer.state();
    bytes = formatLearningCheckpoint(checkpoint);
  }
  const LearningCheckpoint loaded = parseLearningCheckpoint(bytes);
  EXPECT_EQ(loaded.next_input, 3u);
  ASSERT_EQ(loaded.settings.size(), 1u);
  EXPECT_EQ(loaded.settings[0].second, "10");
  OnlineDictionaryLearner learner(parameters);
  PatchShuffleBuffer buffer(60, parameters.batch_size, parameters.seed);
  learner.setState(loaded.learner);
  buffer.setState(loaded.buffer);
  for (int i = 3; i < 5; ++i)
    buffer.add(parts[static_cast<std::size_t>(i)], parts[static_cast<std::size_t>(i)].cols() == 90 ? mask : ObservationMask(), learner);
  buffer.flush(learner);
  EXPECT_EQ(learner.signalsSeen(), whole.signalsSeen());
  EXPECT_TRUE(learner.dictionary() == whole.dictionary());  // bit for bit, not approximately

  // Parameters of another run are refused.
  OnlineDictionaryLearner other({11, 3, 16, 5});
  EXPECT_THROW(other.setState(loaded.learner), Error);
  PatchShuffleBuffer small(10, parameters.batch_size, parameters.seed);
  EXPECT_THROW(small.setState(loaded.buffer), Error);
}

TEST(LearningCheckpoint, DamagedFilesAreRefused)
{
  OnlineDictionaryLearner learner({6, 2, 8, 1});
  learner.update(randomSignals(9, 20, 3));
  LearningCheckpoint checkpoint;
  checkpoint.num_inputs = 1;
  checkpoint.learner = learner.state();
  const std::string bytes = formatLearningCheckpoint(checkpoint);
  EXPECT_NO_THROW(parseLearningCheckpoint(bytes));
  const auto refusal = [](const std::string& damaged) {
    try {
      parseLearningCheckpoint(damaged, "x.pdk");
    } catch (const Error& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal(bytes.substr(0, bytes.size() - 9)).find("checksum"), std::string::npos);
  EXPECT_NE(refusal("PCLPDD\0\x1a" + bytes.substr(8)).find("not a .pdk"), std::string::npos);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x40;
  EXPECT_NE(refusal(flipped).find("checksum"), std::string::npos);
  std::string version = bytes;
  version[8] = 9;
  EXPECT_NE(refusal(version).find("version 9"), std::string::npos);
  EXPECT_NE(refusal(bytes.substr(0, 10)).find("truncated"), std::string::npos);
}

TEST(LearningCheckpoint, ShardStatisticsAddUp)
{
  // Two machines start from the same state and code one shard each; the increments of A and B
  // they report add up to those of one machine coding both shards as one mini-batch, and one atom
  // update on the summed statistics gives that machine's dictionary (the README's reduction).
  const OnlineLearningParameters parameters{8, 3, 40, 2};
  OnlineDictionaryLearner common(parameters);
  common.update(randomSignals(16, 40, 1));
  const auto start = common.state();
  const Eigen::MatrixXd shard_a = randomSignals(16, 40, 2), shard_b = randomSignals(16, 40, 3);
  OnlineDictionaryLearner machine_a(parameters), machine_b(parameters), single(parameters);
  machine_a.setState(start);
  machine_b.setState(start);
  single.setState(start);
  machine_a.update(shard_a);
  machine_b.update(shard_b);
  Eigen::MatrixXd both(16, 80);
  both << shard_a, shard_b;
  single.update(both);
  // Forgetting factor of the step after the first (t = 1) for η signals, as update() computes it.
  const auto beta = [](double eta) {
    const double t = 1.0;
    const double theta = t < eta - 1.0 ? (t + 1.0) * eta : eta * eta + t + 1.0 - eta;
    return (theta + 1.0 - eta) / (theta + 1.0);
  };
  auto merged = start;
  merged.a = beta(80) * start.a + (machine_a.state().a - beta(40) * start.a) + (machine_b.state().a - beta(40) * start.a);
  merged.b = beta(80) * start.b + (machine_a.state().b - beta(40) * start.b) + (machine_b.state().b - beta(40) * start.b);
  EXPECT_LT((merged.a - single.state().a).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((merged.b - single.state().b).cwiseAbs().maxCoeff(), 1e-9);
  OnlineDictionaryLearner reduced(parameters);
  reduced.setState(merged);
  reduced.updateAtoms();
  EXPECT_LT((reduced.dictionary() - single.dictionary()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_GT((reduced.dictionary() - start.dictionary).cwiseAbs().maxCoeff(), 1e-3);  // it did move
}

namespace {

/** `rounds` rounds over three shards against one learner on the combined batches; returns how many
  * atom restarts the sharded learner asked the shards for. `prototypes` (16 × m, or empty for
  * Gaussian signals): signals are their multiples; `masked`: shard 2's signals have hidden bins. */
std::size_t compareShardedRounds(const Eigen::MatrixXd& prototypes, bool masked, int rounds)
{
  const OnlineLearningParameters parameters{24, 2, 60, 7};
  OnlineDictionaryLearner single(parameters), sharded(parameters);
  const auto signalsFor = [&](int cols, std::uint64_t seed) {
    if (prototypes.size() == 0)
      return randomSignals(16, cols, seed);
    std::mt19937_64 rng(seed);
    Eigen::MatrixXd signals(16, cols);
    for (int p = 0; p < cols; ++p)
      signals.col(p) = prototypes.col(static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(prototypes.cols()))) *
                       (1.0 + 0.1 * static_cast<double>(rng() % 7));
    return signals;
  };
  const int sizes[3] = {25, 20, 15};
  std::size_t restarts = 0;
  for (int round = 0; round < rounds; ++round) {
    std::vector<Eigen::MatrixXd> parts;
    std::vector<ObservationMask> masks;
    for (int s = 0; s < 3; ++s) {
      // Shard 3 has nothing every 4th round. With prototypes, the first round has 8 signals for
      // 24 atoms, so 16 start as Gaussian atoms, which such signals leave unused: they restart.
      const bool few = round == 0 && prototypes.size() != 0;
      const int cols = few ? 3 - s / 2 : (s == 2 && round % 4 == 3) ? 0 : sizes[s];
      parts.push_back(signalsFor(cols, 1000 + static_cast<std::uint64_t>(10 * round + s)));
      masks.push_back(masked && s == 1 ? someHidden(16, cols) : ObservationMask());
    }
    const Eigen::Index total = parts[0].cols() + parts[1].cols() + parts[2].cols();
    Eigen::MatrixXd combined(16, total);
    combined << parts[0], parts[1], parts[2];
    ObservationMask combined_mask;
    if (masked) {
      combined_mask = ObservationMask::Constant(16, total, true);
      combined_mask.middleCols(parts[0].cols(), parts[1].cols()) = masks[1];
    }
    single.update(combined, combined_mask);

    if (!sharded.initialised())
      sharded.initialise(combined, combined_mask);
    std::vector<OnlineDictionaryLearner::ShardStatistics> stats;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(24, 24), b = Eigen::MatrixXd::Zero(16, 24);
    for (int s = 0; s < 3; ++s) {
      stats.push_back(sharded.codeShard(parts[s], masks[s]));
      a += stats.back().a;
      b += stats.back().b;
    }
    sharded.applyRound(a, b, total, [&](Eigen::Index p) -> Eigen::VectorXd {
      ++restarts;
      for (int s = 0; s < 3; ++s) {
        if (p < stats[s].filled.cols())
          return stats[s].filled.col(p);
        p -= stats[s].filled.cols();
      }
      ADD_FAILURE() << "restart column beyond the combined batch";
      return Eigen::VectorXd::Zero(16);
    });
    EXPECT_LT((sharded.dictionary() - single.dictionary()).cwiseAbs().maxCoeff(), 1e-9) << "round " << round;
  }
  EXPECT_LT((sharded.state().a - single.state().a).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_EQ(sharded.state().steps, single.state().steps);
  EXPECT_EQ(sharded.state().rng, single.state().rng);  // the same draws, in the same order
  return restarts;
}

}  // namespace

TEST(LearningCheckpoint, RoundsOverShardsTakeTheStepsOfOneLearnerOnTheCombinedBatches)
{
  // Three shards code their parts of every mini-batch against the common dictionary; the summed
  // statistics and applyRound() must give, round after round, the dictionary of one learner fed
  // the combined batches (to 1e-9), with a shard left empty in some rounds, with masks (the EM
  // fill), and with unused atoms restarted from the combined batch.
  compareShardedRounds(Eigen::MatrixXd(), true, 12);
  // Restarts: the first round's 8 prototype signals leave 16 Gaussian atoms unused. They restart
  // as copies of those signals, i.e. of other atoms: exact ties, which the rounding of a sum in
  // another order breaks another way some rounds later (measured: round 3) — so two rounds after.
  EXPECT_GT(compareShardedRounds(randomSignals(16, 10, 99), false, 3), 0u);  // the restart path was taken
  // A shard coded against another dictionary does not give the same step: the check can fail.
  OnlineDictionaryLearner one(OnlineLearningParameters{24, 2, 60, 7}), other(OnlineLearningParameters{24, 2, 60, 8});
  one.update(randomSignals(16, 60, 5));
  other.update(randomSignals(16, 60, 5));
  EXPECT_GT((other.codeShard(randomSignals(16, 25, 6)).a - one.codeShard(randomSignals(16, 25, 6)).a)
                .cwiseAbs()
                .maxCoeff(),
            1e-3);
}

TEST(LearningCheckpoint, ShardProgressRoundTripsBitForBit)
{
  // A sharded run's checkpoint (version 2): every shard's position, buffer, pending sub-batches
  // (one masked, one not) and counters come back as written, and the bytes are stable.
  OnlineDictionaryLearner learner(OnlineLearningParameters{8, 3, 20, 4});
  learner.update(randomSignals(16, 20, 1));
  LearningCheckpoint checkpoint;
  checkpoint.settings = {{"shards", "2"}};
  checkpoint.num_inputs = 5;
  checkpoint.pass = 1;
  checkpoint.learner = learner.state();
  for (int s = 0; s < 2; ++s) {
    PatchShuffleBuffer buffer(30, 10, 7 + static_cast<std::uint64_t>(s));
    OnlineDictionaryLearner sink(OnlineLearningParameters{8, 3, 10, 4});
    buffer.add(randomSignals(16, 34 + s, 3 + static_cast<std::uint64_t>(s)), ObservationMask(), sink);
    ShardProgress shard;
    shard.begun = 2 + static_cast<std::uint64_t>(s);
    shard.next_column = 17;
    shard.streaming = s == 0;
    shard.flushed = s == 1;
    shard.grid_size = 4;
    shard.patches = 100 + static_cast<std::uint64_t>(s);
    shard.patches_streamed = 150;
    shard.patches_coded = 140;
    shard.max_input_patches = 60;
    shard.observed_sum = 97.25;
    shard.skipped = {{3, "bad file"}};
    shard.buffer = buffer.state();
    shard.ready = {randomSignals(16, 10, 9), randomSignals(16, 4, 10)};
    shard.ready_masks = {someHidden(16, 10), ObservationMask()};
    checkpoint.shards.push_back(shard);
  }
  const std::string bytes = formatLearningCheckpoint(checkpoint);
  const LearningCheckpoint back = parseLearningCheckpoint(bytes);
  ASSERT_EQ(back.shards.size(), 2u);
  EXPECT_EQ(formatLearningCheckpoint(back), bytes);
  EXPECT_EQ(back.shards[0].begun, 2u);
  EXPECT_TRUE(back.shards[0].streaming);
  EXPECT_TRUE(back.shards[1].flushed);
  EXPECT_EQ(back.shards[1].skipped, checkpoint.shards[1].skipped);
  EXPECT_EQ(back.shards[0].ready[1], checkpoint.shards[0].ready[1]);
  EXPECT_EQ(back.shards[0].ready_masks[0], checkpoint.shards[0].ready_masks[0]);
  EXPECT_EQ(back.shards[1].buffer.buffered, checkpoint.shards[1].buffer.buffered);
  EXPECT_EQ(back.learner.dictionary, checkpoint.learner.dictionary);
  // Cut anywhere, the file is refused with one line (the checksum, or a size before it).
  for (std::size_t cut : {bytes.size() - 1, bytes.size() / 2, std::size_t(40)})
    EXPECT_THROW(parseLearningCheckpoint(bytes.substr(0, cut)), Error);
}
