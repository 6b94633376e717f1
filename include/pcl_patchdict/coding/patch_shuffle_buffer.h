// PatchShuffleBuffer — a bounded shuffle buffer between streamed patch sets and an online learner:
// patches of many inputs are mixed before they form mini-batches, in memory that does not grow.
#pragma once

#include <pcl_patchdict/coding/dictionary_learning.h>

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <random>
#include <string>

namespace pcl {
namespace patchdict {

/** \brief Online learning (Mairal et al. 2009) assumes i.i.d. signals; patches streamed file after
  * file are not (the last files would dominate the dictionary). The buffer holds at most
  * `capacity` patches: until it is full, patches are stored; after that every incoming patch
  * takes the place of a uniformly chosen buffered one, which goes into the next mini-batch. A
  * full mini-batch (batch_size patches) is fed to the learner. flush() ends a pass: the buffered
  * patches in random order, then the last partial batch. Memory: (capacity + batch_size) patches,
  * whatever the number of inputs; same seed and input order → same batches. */
class PatchShuffleBuffer {
public:
  /** What a checkpoint needs to continue exactly where the buffer was. */
  struct State {
    Eigen::MatrixXd buffered;        ///< n × m, m ≤ capacity
    ObservationMask buffered_mask;   ///< n × m
    Eigen::MatrixXd pending;         ///< n × p, p < batch size: the next mini-batch so far
    ObservationMask pending_mask;    ///< n × p
    std::string rng;                 ///< generator state, text form (operator<<)
    std::uint64_t high_water = 0;    ///< most patches ever buffered
  };

  /** capacity ≥ 1 and batch_size ≥ 1, else Error. */
  PatchShuffleBuffer(std::size_t capacity, int batch_size, std::uint64_t seed);

  /** Where full mini-batches go: the batch (n × b) and its mask (empty when all observed). */
  using BatchSink = std::function<void(const Eigen::MatrixXd& batch, const ObservationMask& mask)>;

  /** Streams the columns of `heights` (n × P; `observed` n × P, or empty for all observed). */
  void add(const Eigen::MatrixXd& heights, const ObservationMask& observed, OnlineDictionaryLearner& learner);
  /** End of a pass: everything buffered goes to the learner; the buffer is empty afterwards. */
  void flush(OnlineDictionaryLearner& learner);
  /** The same with the batches handed to `sink`; addColumn() streams one column, so a caller can
    * stop at the first batch (a shard of a distributed round takes one batch at a time). */
  void add(const Eigen::MatrixXd& heights, const ObservationMask& observed, const BatchSink& sink);
  void addColumn(const Eigen::MatrixXd& heights, const ObservationMask& observed, Eigen::Index column,
                 const BatchSink& sink);
  void flush(const BatchSink& sink);

  std::size_t capacity() const { return capacity_; }
  std::size_t size() const { return static_cast<std::size_t>(size_); }
  /** The most patches the buffer ever held (≤ capacity): the memory bound, as measured. */
  std::size_t highWater() const { return high_water_; }
  /** Mini-batches handed to the learner so far (by this object). */
  std::size_t batchesFed() const { return batches_fed_; }

  State state() const;
  /** Throws Error (one line) for sizes beyond the capacity or batch size, mismatched masks, or a
    * generator text that does not parse. */
  void setState(const State& state);

private:
  void push(const Eigen::MatrixXd& heights, const ObservationMask& observed, Eigen::Index column,
            const BatchSink& sink);
  void toPending(const Eigen::MatrixXd& heights, const ObservationMask& observed, Eigen::Index column,
                 const BatchSink& sink);
  void feed(const BatchSink& sink);
  void reserveRows(Eigen::Index rows);
  /** The mask matches the patches (else Error); the buffer holds their rows. */
  void check(const Eigen::MatrixXd& heights, const ObservationMask& observed);

  std::size_t capacity_;
  int batch_size_;
  Eigen::MatrixXd buffered_;  // n × allocated columns; the first size_ are in use
  ObservationMask buffered_mask_;
  Eigen::Index size_ = 0;
  Eigen::MatrixXd pending_;  // n × batch_size; the first pending_size_ are in use
  ObservationMask pending_mask_;
  Eigen::Index pending_size_ = 0;
  std::size_t high_water_ = 0;
  std::size_t batches_fed_ = 0;
  std::mt19937_64 rng_;
};

}  // namespace patchdict
}  // namespace pcl
