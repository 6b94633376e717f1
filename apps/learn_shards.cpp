// Sharded online learning: mini-batch rounds whose statistics are summed over shards (learn_shards.h).
#include "learn_shards.h"
#include "cli.h"
#include "learn_stream.h"

#include <pcl_patchdict/coding/patch_shuffle_buffer.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/learning_checkpoint_io.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <memory>
#include <sstream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

struct Batch {
  Eigen::MatrixXd signals;
  ObservationMask mask;  ///< empty: all observed
};

int subBatchSize(int batch_size, int shards, int shard)
{
  return batch_size / shards + (shard < batch_size % shards ? 1 : 0);
}

std::uint64_t shardSeed(std::uint64_t seed, int shard)
{
  return seed + 0x632be59bd9b4e019ULL * static_cast<std::uint64_t>(shard);  // shard 0: the run's seed
}

/** Which shard streams each input: largest file first to the shard with the fewest bytes so far
  * (ties: the lower shard), so shards get about equal work when inputs differ in size; each shard
  * keeps its inputs in list order. Depends only on the list and the files' sizes, which a resumed
  * run's fingerprint checks. */
std::vector<int> assignInputs(const std::vector<std::string>& paths, int shards)
{
  std::vector<std::uintmax_t> sizes(paths.size(), 0);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    std::error_code error;  // an unreadable input fails when its shard reads it
    const std::uintmax_t size = std::filesystem::file_size(paths[i], error);
    sizes[i] = error ? 0 : size;
  }
  std::vector<std::size_t> order(paths.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });
  std::vector<std::uintmax_t> load(static_cast<std::size_t>(shards), 0);
  std::vector<int> shard_of(paths.size(), 0);
  for (const std::size_t i : order) {
    const auto lightest = std::min_element(load.begin(), load.end()) - load.begin();
    shard_of[i] = static_cast<int>(lightest);
    load[static_cast<std::size_t>(lightest)] += std::max<std::uintmax_t>(sizes[i], 1);
  }
  return shard_of;
}

/** One shard's stream: its inputs, one column at a time, through its shuffle buffer. */
class ShardStream {
public:
  ShardStream(const ShardedLearningJob& job, int shard, const std::vector<int>& shard_of)
      : job_(job), shard_(shard),
        buffer_(job.buffer_capacity, subBatchSize(job.parameters.batch_size, job.shards, shard),
                shardSeed(job.parameters.seed, shard)),
        cache_(job.patch_cache, job.paths.size()), grid_size_(job.grid_size)
  {
    for (std::size_t i = 0; i < job.paths.size(); ++i)
      if (shard_of[i] == shard)
        inputs_.push_back(i);
  }

  void startPass(int pass)
  {
    pass_ = pass;
    cursor_ = 0;
    flushed_ = false;
  }

  /** The shard's next sub-batch of this pass; false when the pass has nothing more. */
  bool next(Batch& out)
  {
    const PatchShuffleBuffer::BatchSink sink = [this](const Eigen::MatrixXd& batch, const ObservationMask& mask) {
      ready_.push_back({batch, mask});
    };
    while (ready_.empty()) {
      if (column_ < current_.heights.cols()) {
        buffer_.addColumn(current_.heights, current_mask_, column_++, sink);
      } else if (cursor_ < inputs_.size()) {
        read(inputs_[cursor_++]);
      } else if (!flushed_) {
        buffer_.flush(sink);
        flushed_ = true;
      } else {
        return false;
      }
    }
    out = std::move(ready_.front());
    ready_.pop_front();
    coded += static_cast<std::uint64_t>(out.signals.cols());
    return true;
  }

  /** Where the shard stands at a round's end (for a checkpoint). */
  ShardProgress progress() const
  {
    ShardProgress p;
    p.begun = cursor_;
    p.streaming = column_ < current_.heights.cols();
    p.next_column = p.streaming ? static_cast<std::uint64_t>(column_) : 0;
    p.flushed = flushed_;
    p.grid_size = grid_size_;
    p.patches = patches;
    p.patches_streamed = streamed;
    p.patches_coded = coded;
    p.max_input_patches = max_input_patches;
    p.observed_sum = observed_sum;
    p.skipped = skipped;
    p.buffer = buffer_.state();
    for (const Batch& batch : ready_) {
      p.ready.push_back(batch.signals);
      p.ready_masks.push_back(batch.mask);
    }
    return p;
  }

  /** Continues from a checkpoint's progress, in pass `pass`: the input it was streaming is read
    * again (without counting it twice). */
  void restore(const ShardProgress& p, int pass)
  {
    pass_ = pass;
    if (p.begun > inputs_.size() || (p.streaming && p.begun == 0) || p.ready.size() != p.ready_masks.size())
      throw Error("cannot resume: shard " + std::to_string(shard_ + 1) + "'s progress does not fit its inputs");
    cursor_ = static_cast<std::size_t>(p.begun);
    flushed_ = p.flushed;
    grid_size_ = p.grid_size;
    patches = p.patches;
    streamed = p.patches_streamed;
    coded = p.patches_coded;
    max_input_patches = static_cast<std::size_t>(p.max_input_patches);
    observed_sum = p.observed_sum;
    skipped = p.skipped;
    buffer_.setState(p.buffer);
    ready_.clear();
    for (std::size_t i = 0; i < p.ready.size(); ++i)
      ready_.push_back({p.ready[i], p.ready_masks[i]});
    current_ = PatchSet();
    column_ = 0;
    if (p.streaming) {
      const std::string& path = job_.paths[inputs_[cursor_ - 1]];
      current_ = loadInputPatches(path, job_.surface_options, grid_size_);
      if (p.next_column >= static_cast<std::uint64_t>(current_.heights.cols()))
        throw Error("cannot resume: '" + path + "' has fewer patches than when the checkpoint was written");
      column_ = static_cast<Eigen::Index>(p.next_column);
      current_mask_ = current_.observed.all() ? ObservationMask() : current_.observed;
    }
  }

  int index() const { return shard_; }
  std::size_t begunThisRun() const { return begun_this_run_; }
  std::size_t highWater() const { return buffer_.highWater(); }
  std::uintmax_t cacheBytes() const { return cache_.bytes(); }

  std::uint64_t patches = 0, streamed = 0, coded = 0;
  double observed_sum = 0.0;
  std::size_t max_input_patches = 0, cache_reads = 0;
  std::vector<std::pair<std::uint64_t, std::string>> skipped;

private:
  void read(std::size_t i)
  {
    ++begun_this_run_;
    const std::string& path = job_.paths[i];
    const std::string where = "input " + std::to_string(i + 1) + "/" + std::to_string(job_.paths.size());
    current_ = PatchSet();
    column_ = 0;
    bool bad = false;
    try {
      if (cache_.has(i)) {
        current_ = cache_.load(i);
        ++cache_reads;
      } else {
        current_ = loadInputPatches(path, job_.surface_options, grid_size_);
        if (pass_ + 1 < job_.passes && !readsAsPatchSet(path))
          cache_.store(i, current_, job_.quiet);
      }
    } catch (const Error& error) {
      if (!job_.skip_bad)
        throw Error(where + ": " + error.what() + " (--skip-bad skips bad inputs)");
      if (pass_ == 0) {  // a bad input fails the same way on every pass: reported once
        note(job_.quiet, "  skipped " + where + ": " + error.what());
        skipped.emplace_back(i, error.what());
      }
      current_ = PatchSet();
      bad = true;
    }
    const std::size_t count = current_.numPatches();
    if (count > 0) {
      if (grid_size_ == 0)
        grid_size_ = current_.grid_size;
      if (pass_ == 0) {
        patches += count;
        observed_sum += current_.observedFraction() * static_cast<double>(count);
      }
      max_input_patches = std::max(max_input_patches, count);
      streamed += count;
      current_mask_ = current_.observed.all() ? ObservationMask() : current_.observed;
    }
    char line[200];
    std::snprintf(line, sizeof line, "  shard %d/%d, pass %d/%d, %s: %zu patches ", shard_ + 1, job_.shards,
                  pass_ + 1, job_.passes, where.c_str(), count);
    note(job_.quiet, line + std::filesystem::path(path).filename().string() + (bad ? " (skipped)" : ""));
  }

  const ShardedLearningJob& job_;
  int shard_;
  std::vector<std::size_t> inputs_;
  PatchShuffleBuffer buffer_;
  PatchCache cache_;
  int grid_size_;
  int pass_ = 0;
  std::size_t cursor_ = 0;
  bool flushed_ = false;
  PatchSet current_;
  ObservationMask current_mask_;
  Eigen::Index column_ = 0;
  std::deque<Batch> ready_;
  std::size_t begun_this_run_ = 0;
};

std::string bytesOf(const Batch& batch)
{
  const Eigen::Index rows = batch.signals.rows(), cols = batch.signals.cols();
  std::string bytes(2 * sizeof(std::int64_t) + static_cast<std::size_t>(rows * cols) * (sizeof(double) + 1), '\0');
  const std::int64_t size[2] = {rows, cols};
  std::memcpy(bytes.data(), size, sizeof size);
  std::memcpy(bytes.data() + sizeof size, batch.signals.data(), static_cast<std::size_t>(rows * cols) * sizeof(double));
  char* mask = bytes.data() + sizeof size + static_cast<std::size_t>(rows * cols) * sizeof(double);
  for (Eigen::Index k = 0; k < rows * cols; ++k)
    mask[k] = batch.mask.size() == 0 || batch.mask.data()[k] ? 1 : 0;
  return bytes;
}

/** The round's combined batch (every shard's sub-batch in shard order), on every rank. */
Batch combinedBatch(const std::vector<Batch>& local, const Ranks& ranks, Eigen::Index rows)
{
  std::vector<Batch> parts;
  if (ranks.size() == 1) {
    parts = local;
  } else {
    for (const std::string& bytes : ranks.allGatherBytes(bytesOf(local.front()))) {
      std::int64_t size[2];
      std::memcpy(size, bytes.data(), sizeof size);
      Batch part;
      part.signals.resize(size[0], size[1]);
      part.mask.resize(size[0], size[1]);
      const std::size_t count = static_cast<std::size_t>(size[0] * size[1]);
      std::memcpy(part.signals.data(), bytes.data() + sizeof size, count * sizeof(double));
      for (std::size_t k = 0; k < count; ++k)
        part.mask.data()[k] = bytes[sizeof size + count * sizeof(double) + k] != 0;
      parts.push_back(std::move(part));
    }
  }
  Eigen::Index cols = 0;
  bool masked = false;
  for (const Batch& part : parts) {
    cols += part.signals.cols();
    masked = masked || (part.mask.size() != 0 && !part.mask.all());
  }
  Batch all;
  all.signals.resize(rows, cols);
  if (masked)
    all.mask.resize(rows, cols);
  Eigen::Index at = 0;
  for (const Batch& part : parts) {
    const Eigen::Index c = part.signals.cols();
    if (c == 0)
      continue;
    all.signals.middleCols(at, c) = part.signals;
    if (masked) {
      if (part.mask.size() == 0)
        all.mask.middleCols(at, c).setConstant(true);
      else
        all.mask.middleCols(at, c) = part.mask;
    }
    at += c;
  }
  return all;
}

/** Skipped inputs as bytes between ranks: index, reason length, reason (any characters). */
std::string skippedBytes(const std::vector<std::pair<std::uint64_t, std::string>>& skipped)
{
  std::string bytes;
  for (const auto& entry : skipped)
    bytes += std::to_string(entry.first) + ' ' + std::to_string(entry.second.size()) + ' ' + entry.second;
  return bytes;
}

void readSkipped(const std::string& bytes, std::vector<std::pair<std::uint64_t, std::string>>& skipped)
{
  std::size_t at = 0;
  while (at < bytes.size()) {
    std::size_t end = 0;
    const std::uint64_t index = std::stoull(bytes.substr(at), &end);
    at += end + 1;
    const std::size_t length = std::stoull(bytes.substr(at), &end);
    at += end + 1;
    skipped.emplace_back(index, bytes.substr(at, length));
    at += length;
  }
}

/** The shards' counters, gathered so that every rank holds every shard's (in shard order). */
void gatherCounters(const std::vector<std::unique_ptr<ShardStream>>& local, const Ranks& ranks,
                    ShardedLearningResult& result)
{
  std::vector<std::int64_t> counts;
  std::vector<double> sums;
  std::string skipped;
  for (const auto& shard : local) {
    counts.insert(counts.end(), {static_cast<std::int64_t>(shard->patches), static_cast<std::int64_t>(shard->streamed),
                                 static_cast<std::int64_t>(shard->coded),
                                 static_cast<std::int64_t>(shard->max_input_patches),
                                 static_cast<std::int64_t>(shard->highWater()),
                                 static_cast<std::int64_t>(shard->cache_reads),
                                 static_cast<std::int64_t>(shard->cacheBytes())});
    sums.push_back(shard->observed_sum);
    skipped += skippedBytes(shard->skipped);
  }
  const std::vector<std::int64_t> all = ranks.allGather(counts);
  const std::vector<double> all_sums = ranks.allGather(sums);
  for (std::size_t s = 0; s < all_sums.size(); ++s) {
    const std::int64_t* c = &all[7 * s];
    result.patches += static_cast<std::uint64_t>(c[0]);
    result.patches_streamed += static_cast<std::uint64_t>(c[1]);
    result.patches_coded.push_back(static_cast<std::uint64_t>(c[2]));
    result.max_input_patches = std::max(result.max_input_patches, static_cast<std::size_t>(c[3]));
    result.max_buffered = std::max(result.max_buffered, static_cast<std::size_t>(c[4]));
    result.cache_reads += static_cast<std::size_t>(c[5]);
    result.cache_bytes += static_cast<std::uint64_t>(c[6]);
    result.observed_sum += all_sums[s];
  }
  for (const std::string& bytes : ranks.allGatherBytes(skipped))
    readSkipped(bytes, result.skipped);
  std::sort(result.skipped.begin(), result.skipped.end());
}

/** Adds the seconds since the last call to one of the round's parts. */
class PartClock {
public:
  void to(double& part)
  {
    const auto now = std::chrono::steady_clock::now();
    part += std::chrono::duration<double>(now - last_).count();
    last_ = now;
  }

private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

/** One sharded run: this process's shards, the common learner, the rounds. */
class ShardedRun {
public:
  ShardedRun(const ShardedLearningJob& job, const Ranks& ranks) : job_(job), ranks_(ranks), learner_(job.parameters)
  {
    if (job.shards < 1 || job.parameters.batch_size < job.shards)
      ranks.fail("the batch (" + std::to_string(job.parameters.batch_size) + ") must hold at least one patch per shard (" +
                 std::to_string(job.shards) + ")");
    if (ranks.size() > 1 && ranks.size() != job.shards)
      ranks.fail(std::to_string(ranks.size()) + " ranks for " + std::to_string(job.shards) + " shards");
    // Every rank must deal the same inputs alike (names and sizes, as a resumed run checks).
    const std::vector<std::int64_t> fingerprints =
        ranks.allGather(std::vector<std::int64_t>{static_cast<std::int64_t>(job.checkpoint.inputs_fingerprint)});
    for (const std::int64_t fingerprint : fingerprints)
      if (fingerprint != fingerprints.front())
        ranks.fail("the ranks see different inputs (names or sizes): they must share the same files");
    ranks.agree([&]() {
      const std::vector<int> shard_of = assignInputs(job.paths, job.shards);
      for (int s = 0; s < job.shards; ++s)
        if (ranks.size() == 1 || s == ranks.rank())
          local_.push_back(std::make_unique<ShardStream>(job, s, shard_of));
      if (job.resume != nullptr)
        resume(*job.resume);
    });
  }

  /** The passes, to the end or to a stop; then the counters of every shard. */
  ShardedLearningResult run()
  {
    for (int pass = first_pass_; pass < job_.passes && result_.complete; ++pass) {
      if (job_.resume == nullptr || pass != first_pass_)
        for (auto& shard : local_)
          shard->startPass(pass);
      while (round()) {
        if (job_.stop_after > 0 && begun_ >= job_.stop_after) {
          result_.complete = false;
          checkpoint(pass);
          break;
        }
        if (job_.checkpoint_every > 0 && begun_ / job_.checkpoint_every > checkpoints_due_) {
          checkpoints_due_ = begun_ / job_.checkpoint_every;
          checkpoint(pass);
        }
      }
    }
    gatherCounters(local_, ranks_, result_);
    result_.steps = static_cast<std::size_t>(learner_.state().steps);
    result_.inputs_begun = begun_;
    if (!result_.complete)
      return result_;
    if (result_.patches == 0 || !learner_.initialised())
      ranks_.fail(result_.skipped.size() == job_.paths.size() ? "every input was bad and skipped"
                                                              : "the inputs hold no patches");
    result_.dictionary = learner_.dictionary();
    result_.grid_size = gridSize();
    checkpoint(job_.passes);  // the finished state: resuming from it only writes the dictionary again
    return result_;
  }

private:
  void resume(const LearningCheckpoint& saved)
  {
    if (saved.shards.size() != static_cast<std::size_t>(job_.shards))
      throw Error("cannot resume: the checkpoint holds " + std::to_string(saved.shards.size()) + " shards, the run " +
                  std::to_string(job_.shards));
    learner_.setState(saved.learner);
    first_pass_ = static_cast<int>(saved.pass);
    rows_ = saved.learner.dictionary.rows();
    for (auto& shard : local_)
      shard->restore(saved.shards[static_cast<std::size_t>(shard->index())], std::min(first_pass_, job_.passes - 1));
  }

  int gridSize() const { return static_cast<int>(std::lround(std::sqrt(static_cast<double>(rows_)))); }

  /** One mini-batch round; false when the pass is over on every shard. */
  bool round()
  {
    // 1. Every shard's next sub-batch; every rank learns every shard's size.
    std::vector<Batch> batches(local_.size());
    std::vector<std::int64_t> header;
    ranks_.agree([&]() {
      for (std::size_t i = 0; i < local_.size(); ++i) {
        const bool got = local_[i]->next(batches[i]);
        header.push_back(got ? batches[i].signals.rows() : 0);
        header.push_back(got ? batches[i].signals.cols() : 0);
        header.push_back(static_cast<std::int64_t>(local_[i]->begunThisRun()));
      }
    });
    clock_.to(result_.seconds_read);
    const std::vector<std::int64_t> sizes = ranks_.allGather(header);
    std::vector<Eigen::Index> offsets(1, 0);
    begun_ = 0;  // inputs begun in this run, over all shards
    for (int s = 0; s < job_.shards; ++s) {
      const std::int64_t* shard = &sizes[3 * static_cast<std::size_t>(s)];
      if (shard[0] != 0 && rows_ != 0 && shard[0] != rows_)
        ranks_.fail("shard " + std::to_string(s + 1) + "'s patches have " + std::to_string(shard[0]) +
                    " bins, the others' " + std::to_string(rows_) + " (give --grid)");
      if (shard[0] != 0)
        rows_ = shard[0];
      offsets.push_back(offsets.back() + shard[1]);
      begun_ += static_cast<std::size_t>(shard[2]);
    }
    if (offsets.back() == 0)
      return false;
    // 2. The first round's combined signals initialise the atoms on every rank.
    if (!learner_.initialised()) {
      const Batch first = combinedBatch(batches, ranks_, rows_);
      ranks_.agree([&]() { learner_.initialise(first.signals, first.mask); });
    }
    clock_.to(result_.seconds_exchange);
    update(batches, offsets);
    return true;
  }

  /** 3. Every shard codes its sub-batch, [A | B] summed over the shards in the fixed tree; 4. the
    * same step on every rank, a restarted atom's column broadcast by the shard that holds it. */
  void update(const std::vector<Batch>& batches, const std::vector<Eigen::Index>& offsets)
  {
    const Eigen::Index k = job_.parameters.num_atoms;
    std::vector<OnlineDictionaryLearner::ShardStatistics> stats(local_.size());
    std::vector<std::vector<double>> parts(local_.size());
    ranks_.agree([&]() {
      for (std::size_t i = 0; i < local_.size(); ++i) {
        stats[i] = learner_.codeShard(batches[i].signals, batches[i].mask);
        parts[i].resize(static_cast<std::size_t>(k * k + rows_ * k));
        Eigen::Map<Eigen::MatrixXd>(parts[i].data(), k, k) = stats[i].a;
        Eigen::Map<Eigen::MatrixXd>(parts[i].data() + k * k, rows_, k) = stats[i].b;
      }
    });
    clock_.to(result_.seconds_code);
    treeSum(parts);
    ranks_.sum(parts[0].data(), parts[0].size());
    clock_.to(result_.seconds_exchange);
    const Eigen::MatrixXd a = Eigen::Map<const Eigen::MatrixXd>(parts[0].data(), k, k);
    const Eigen::MatrixXd b = Eigen::Map<const Eigen::MatrixXd>(parts[0].data() + k * k, rows_, k);
    const auto restart = [&](Eigen::Index p) -> Eigen::VectorXd {
      const int owner = static_cast<int>(std::upper_bound(offsets.begin(), offsets.end(), p) - offsets.begin()) - 1;
      Eigen::VectorXd column = Eigen::VectorXd::Zero(rows_);
      for (std::size_t i = 0; i < local_.size(); ++i)
        if (local_[i]->index() == owner)
          column = stats[i].filled.col(p - offsets[static_cast<std::size_t>(owner)]);
      ranks_.broadcast(column.data(), static_cast<std::size_t>(rows_), owner);
      return column;
    };
    learner_.applyRound(a, b, offsets.back(), restart);
    clock_.to(result_.seconds_update);
  }

  /** Rank 0 writes the run's state: the common learner and every shard's progress (gathered). */
  void checkpoint(int pass)
  {
    if (job_.checkpoint_path.empty())
      return;
    LearningCheckpoint checkpoint = job_.checkpoint;
    checkpoint.pass = static_cast<std::uint32_t>(pass);
    checkpoint.grid_size = gridSize();
    checkpoint.learner = learner_.state();
    std::string mine;  // one shard's progress, in the checkpoint's own bytes (between ranks)
    ranks_.agree([&]() {
      if (ranks_.size() == 1) {
        for (const auto& shard : local_)
          checkpoint.shards.push_back(shard->progress());
        return;
      }
      LearningCheckpoint part;
      part.num_inputs = job_.paths.size();
      part.shards.push_back(local_.front()->progress());
      mine = formatLearningCheckpoint(part);
    });
    if (ranks_.size() > 1) {
      const std::vector<std::string> parts = ranks_.gatherBytes(mine);
      ranks_.agree([&]() {
        for (const std::string& bytes : parts)
          checkpoint.shards.push_back(parseLearningCheckpoint(bytes, "a rank's progress").shards.front());
      });
    }
    ranks_.agree([&]() {
      if (ranks_.rank() == 0)
        saveLearningCheckpoint(job_.checkpoint_path, checkpoint);
    });
    ++result_.checkpoints_written;
  }

  const ShardedLearningJob& job_;
  const Ranks& ranks_;
  OnlineDictionaryLearner learner_;
  std::vector<std::unique_ptr<ShardStream>> local_;
  ShardedLearningResult result_;
  Eigen::Index rows_ = 0;
  int first_pass_ = 0;
  std::size_t begun_ = 0, checkpoints_due_ = 0;
  PartClock clock_;
};

}  // namespace

ShardedLearningResult learnSharded(const ShardedLearningJob& job, const Ranks& ranks)
{
  ShardedRun run(job, ranks);
  return run.run();
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
