// Bounded shuffle buffer feeding an online dictionary learner (Mairal et al. 2009 assume i.i.d.
// mini-batches; streamed files are not): eviction of a uniformly chosen patch, as shuffle buffers do.
#include "coding/learning_common.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/patch_shuffle_buffer.h>

#include <algorithm>

namespace pcl {
namespace patchdict {

namespace {

constexpr std::uint64_t kSeedSalt = 0x9e3779b97f4a7c15ULL;  // the buffer's stream differs from the learner's

}  // namespace

PatchShuffleBuffer::PatchShuffleBuffer(std::size_t capacity, int batch_size, std::uint64_t seed)
    : capacity_(capacity), batch_size_(batch_size), rng_(seed ^ kSeedSalt)
{
  if (capacity < 1 || batch_size < 1)
    throw Error("shuffle buffer: capacity and batch size must be at least 1");
}

void PatchShuffleBuffer::reserveRows(Eigen::Index rows)
{
  if (pending_.rows() == rows)
    return;
  if (size_ != 0 || pending_size_ != 0)
    throw Error("shuffle buffer: patches have " + std::to_string(rows) + " bins, the buffered ones " +
                std::to_string(pending_.rows()));
  pending_.resize(rows, batch_size_);
  pending_mask_.resize(rows, batch_size_);
  buffered_.resize(rows, 0);
  buffered_mask_.resize(rows, 0);
}

namespace {

PatchShuffleBuffer::BatchSink learnerSink(OnlineDictionaryLearner& learner)
{
  return [&learner](const Eigen::MatrixXd& batch, const ObservationMask& mask) { learner.update(batch, mask); };
}

}  // namespace

void PatchShuffleBuffer::add(const Eigen::MatrixXd& heights, const ObservationMask& observed,
                             OnlineDictionaryLearner& learner)
{
  add(heights, observed, learnerSink(learner));
}

void PatchShuffleBuffer::flush(OnlineDictionaryLearner& learner)
{
  flush(learnerSink(learner));
}

void PatchShuffleBuffer::add(const Eigen::MatrixXd& heights, const ObservationMask& observed, const BatchSink& sink)
{
  if (heights.cols() == 0)
    return;
  check(heights, observed);
  for (Eigen::Index p = 0; p < heights.cols(); ++p)
    push(heights, observed, p, sink);
}

void PatchShuffleBuffer::addColumn(const Eigen::MatrixXd& heights, const ObservationMask& observed,
                                   Eigen::Index column, const BatchSink& sink)
{
  if (column < 0 || column >= heights.cols())
    throw Error("shuffle buffer: column " + std::to_string(column) + " of " + std::to_string(heights.cols()));
  check(heights, observed);
  push(heights, observed, column, sink);
}

void PatchShuffleBuffer::check(const Eigen::MatrixXd& heights, const ObservationMask& observed)
{
  if (observed.size() != 0 && (observed.rows() != heights.rows() || observed.cols() != heights.cols()))
    throw Error("shuffle buffer: the mask does not match the patches");
  reserveRows(heights.rows());
}

void PatchShuffleBuffer::push(const Eigen::MatrixXd& heights, const ObservationMask& observed, Eigen::Index column,
                              const BatchSink& sink)
{
  if (static_cast<std::size_t>(size_) < capacity_) {
    if (size_ == buffered_.cols()) {
      // Grow geometrically up to the capacity: a small job does not pay for a large buffer.
      const Eigen::Index grown = std::min<Eigen::Index>(static_cast<Eigen::Index>(capacity_),
                                                        std::max<Eigen::Index>(2 * buffered_.cols(), 1024));
      buffered_.conservativeResize(Eigen::NoChange, grown);
      buffered_mask_.conservativeResize(Eigen::NoChange, grown);
    }
    buffered_.col(size_) = heights.col(column);
    if (observed.size() != 0)
      buffered_mask_.col(size_) = observed.col(column);
    else
      buffered_mask_.col(size_).setConstant(true);
    ++size_;
    high_water_ = std::max(high_water_, static_cast<std::size_t>(size_));
    return;
  }
  const Eigen::Index slot = static_cast<Eigen::Index>(rng_() % static_cast<std::uint64_t>(size_));
  toPending(buffered_, buffered_mask_, slot, sink);
  buffered_.col(slot) = heights.col(column);
  if (observed.size() != 0)
    buffered_mask_.col(slot) = observed.col(column);
  else
    buffered_mask_.col(slot).setConstant(true);
}

void PatchShuffleBuffer::toPending(const Eigen::MatrixXd& heights, const ObservationMask& observed,
                                   Eigen::Index column, const BatchSink& sink)
{
  pending_.col(pending_size_) = heights.col(column);
  pending_mask_.col(pending_size_) = observed.col(column);
  if (++pending_size_ == batch_size_)
    feed(sink);
}

void PatchShuffleBuffer::feed(const BatchSink& sink)
{
  if (pending_size_ == 0)
    return;
  const Eigen::MatrixXd batch = pending_.leftCols(pending_size_);
  const ObservationMask mask = pending_mask_.leftCols(pending_size_);
  pending_size_ = 0;
  ++batches_fed_;
  // An all-observed batch goes through Batch-OMP (the mask-free path), as a fully observed file did.
  sink(batch, mask.all() ? ObservationMask() : mask);
}

void PatchShuffleBuffer::flush(const BatchSink& sink)
{
  // Fisher–Yates over the buffered patches, each sent on as it is drawn.
  for (Eigen::Index remaining = size_; remaining > 0; --remaining) {
    const Eigen::Index pick = static_cast<Eigen::Index>(rng_() % static_cast<std::uint64_t>(remaining));
    toPending(buffered_, buffered_mask_, pick, sink);
    if (pick != remaining - 1) {
      buffered_.col(pick) = buffered_.col(remaining - 1);
      buffered_mask_.col(pick) = buffered_mask_.col(remaining - 1);
    }
  }
  size_ = 0;
  feed(sink);
}

PatchShuffleBuffer::State PatchShuffleBuffer::state() const
{
  State state;
  state.buffered = buffered_.leftCols(size_);
  state.buffered_mask = buffered_mask_.leftCols(size_);
  state.pending = pending_.leftCols(pending_size_);
  state.pending_mask = pending_mask_.leftCols(pending_size_);
  state.rng = detail::generatorText(rng_);
  state.high_water = high_water_;
  return state;
}

void PatchShuffleBuffer::setState(const State& state)
{
  const Eigen::Index rows = std::max(state.buffered.rows(), state.pending.rows());
  if (static_cast<std::size_t>(state.buffered.cols()) > capacity_ || state.pending.cols() >= batch_size_ ||
      state.high_water > capacity_)
    throw Error("shuffle buffer: the saved state holds more patches than the buffer or batch size allow");
  if ((state.buffered.size() != 0 && state.buffered.rows() != rows) ||
      (state.pending.size() != 0 && state.pending.rows() != rows) ||
      state.buffered_mask.rows() != state.buffered.rows() || state.buffered_mask.cols() != state.buffered.cols() ||
      state.pending_mask.rows() != state.pending.rows() || state.pending_mask.cols() != state.pending.cols())
    throw Error("shuffle buffer: the saved state's matrices disagree in size");
  const std::mt19937_64 rng = detail::generatorFromText(state.rng, "shuffle buffer");
  size_ = 0;
  pending_size_ = 0;
  pending_.resize(0, 0);
  if (rows > 0) {
    reserveRows(rows);
    buffered_ = state.buffered;
    buffered_mask_ = state.buffered_mask;
    size_ = state.buffered.cols();
    pending_.leftCols(state.pending.cols()) = state.pending;
    pending_mask_.leftCols(state.pending.cols()) = state.pending_mask;
    pending_size_ = state.pending.cols();
  }
  high_water_ = static_cast<std::size_t>(state.high_water);
  rng_ = rng;
}

}  // namespace patchdict
}  // namespace pcl
