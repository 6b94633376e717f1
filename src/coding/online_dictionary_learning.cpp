// Online dictionary learning (Mairal, Bach, Ponce & Sapiro, "Online dictionary learning for sparse
// coding", ICML 2009): per mini-batch, code with OMP, fold the codes into the sufficient statistics
// A = Σ ααᵀ and B = Σ xαᵀ (with the mini-batch forgetting factor), then one block-coordinate pass
// over the atoms. Unit atom norms are kept (not ≤ 1) because OMP selects by correlation.
#include "coding/learning_common.h"

#include <pcl_patchdict/core/error.h>

#include <Eigen/Dense>

#include <algorithm>
#include <numeric>

namespace pcl {
namespace patchdict {

OnlineDictionaryLearner::OnlineDictionaryLearner(const OnlineLearningParameters& parameters)
    : parameters_(parameters), rng_(parameters.seed)
{
  if (parameters.num_atoms < 1 || parameters.sparsity < 1 || parameters.batch_size < 1)
    throw Error("online learning: atoms, sparsity and batch size must be at least 1");
}

void OnlineDictionaryLearner::update(const Eigen::MatrixXd& batch, const ObservationMask& mask)
{
  if (!initialised())
    initialise(batch, mask);
  const ShardStatistics shard = codeShard(batch, mask);
  applyRound(shard.a, shard.b, batch.cols(),
             [&](Eigen::Index p) -> Eigen::VectorXd { return shard.filled.col(p); });
}

void OnlineDictionaryLearner::initialise(const Eigen::MatrixXd& batch, const ObservationMask& mask)
{
  if (initialised())
    throw Error("online learning: the dictionary is initialised already");
  detail::checkTrainingData(batch, mask, parameters_.num_atoms, parameters_.sparsity);
  dictionary_ = detail::initialAtoms(batch, mask, parameters_.num_atoms, rng_);
  a_ = Eigen::MatrixXd::Zero(parameters_.num_atoms, parameters_.num_atoms);
  b_ = Eigen::MatrixXd::Zero(batch.rows(), parameters_.num_atoms);
}

OnlineDictionaryLearner::ShardStatistics OnlineDictionaryLearner::codeShard(const Eigen::MatrixXd& batch,
                                                                           const ObservationMask& mask) const
{
  if (!initialised())
    throw Error("online learning: a shard is coded before the dictionary is initialised");
  ShardStatistics shard;
  if (batch.cols() == 0) {  // a shard with nothing this round adds nothing
    shard.a = Eigen::MatrixXd::Zero(a_.rows(), a_.cols());
    shard.b = Eigen::MatrixXd::Zero(b_.rows(), b_.cols());
    shard.filled.resize(b_.rows(), 0);
    return shard;
  }
  if (batch.rows() != dictionary_.rows())
    throw Error("online learning: batch signals have " + std::to_string(batch.rows()) + " entries, the dictionary " +
                std::to_string(dictionary_.rows()));
  detail::checkTrainingData(batch, mask, parameters_.num_atoms, parameters_.sparsity);
  const SparseCodes codes = detail::codeSignals(dictionary_, batch, mask, parameters_.sparsity);
  // EM step for missing entries: what the current dictionary predicts stands in for them.
  if (mask.size() != 0)
    shard.filled = mask.select(batch, Eigen::MatrixXd(dictionary_ * codes));
  else
    shard.filled = batch;
  // A = Σ α αᵀ and B = Σ x αᵀ over the codes' non-zeros only (S² and n·S per signal, not the K²
  // and n·K of dense products), signal after signal: a fixed order, whatever the batch.
  shard.a = Eigen::MatrixXd::Zero(a_.rows(), a_.cols());
  shard.b = Eigen::MatrixXd::Zero(b_.rows(), b_.cols());
  for (Eigen::Index p = 0; p < codes.outerSize(); ++p) {
    for (SparseCodes::InnerIterator i(codes, p); i; ++i) {
      for (SparseCodes::InnerIterator j(codes, p); j; ++j)
        shard.a(i.index(), j.index()) += i.value() * j.value();
      shard.b.col(i.index()) += i.value() * shard.filled.col(p);
    }
  }
  return shard;
}

void OnlineDictionaryLearner::applyRound(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, Eigen::Index signals,
                                         const std::function<Eigen::VectorXd(Eigen::Index)>& restart_column)
{
  if (!initialised())
    throw Error("online learning: a round is applied before the dictionary is initialised");
  if (a.rows() != a_.rows() || a.cols() != a_.cols() || b.rows() != b_.rows() || b.cols() != b_.cols())
    throw Error("online learning: the round's statistics disagree in size with the learner's");
  if (signals < 1)
    throw Error("online learning: a round without signals");
  // Forgetting factor of the mini-batch variant (Mairal et al. 2009, sec. 3.4; as scikit-learn).
  const double eta = static_cast<double>(signals);
  const double t = static_cast<double>(steps_);
  const double theta = t < eta - 1.0 ? (t + 1.0) * eta : eta * eta + t + 1.0 - eta;
  const double beta = (theta + 1.0 - eta) / (theta + 1.0);
  a_ = beta * a_ + a;
  b_ = beta * b_ + b;

  blockCoordinateUpdate(signals, &restart_column);
  seen_ += static_cast<std::size_t>(signals);
  ++steps_;
}

void OnlineDictionaryLearner::blockCoordinateUpdate(Eigen::Index columns,
                                                    const std::function<Eigen::VectorXd(Eigen::Index)>* restart_column)
{
  const int num_atoms = parameters_.num_atoms;
  for (int j = 0; j < num_atoms; ++j) {
    if (a_(j, j) < 1e-6) {
      if (restart_column == nullptr || columns == 0)
        continue;
      // An atom nobody uses: restart it from a signal of this batch (as SPAMS does).
      std::uniform_int_distribution<Eigen::Index> pick(0, columns - 1);
      const Eigen::VectorXd candidate = (*restart_column)(pick(rng_));
      const double norm = candidate.norm();
      if (norm > 1e-12)
        dictionary_.col(j) = candidate / norm;
      continue;
    }
    Eigen::VectorXd atom = dictionary_.col(j) + (b_.col(j) - dictionary_ * a_.col(j)) / a_(j, j);
    const double norm = atom.norm();
    if (norm > 1e-12)
      dictionary_.col(j) = atom / norm;
  }
}

void OnlineDictionaryLearner::updateAtoms()
{
  if (dictionary_.size() == 0)
    throw Error("online learning: no dictionary to update yet");
  blockCoordinateUpdate(0, nullptr);
}

OnlineDictionaryLearner::State OnlineDictionaryLearner::state() const
{
  State state;
  state.parameters = parameters_;
  state.dictionary = dictionary_;
  state.a = a_;
  state.b = b_;
  state.seen = seen_;
  state.steps = steps_;
  state.rng = detail::generatorText(rng_);
  return state;
}

void OnlineDictionaryLearner::setState(const State& state)
{
  const OnlineLearningParameters& p = state.parameters;
  if (p.num_atoms != parameters_.num_atoms || p.sparsity != parameters_.sparsity ||
      p.batch_size != parameters_.batch_size || p.seed != parameters_.seed)
    throw Error("online learning: the saved state was made with other parameters (atoms " +
                std::to_string(p.num_atoms) + ", sparsity " + std::to_string(p.sparsity) + ", batch " +
                std::to_string(p.batch_size) + ", seed " + std::to_string(p.seed) + ")");
  const Eigen::Index k = parameters_.num_atoms;
  const Eigen::Index n = state.dictionary.rows();
  const bool empty = state.dictionary.size() == 0;
  if (empty ? (state.a.size() != 0 || state.b.size() != 0)
            : (state.dictionary.cols() != k || state.a.rows() != k || state.a.cols() != k || state.b.rows() != n ||
               state.b.cols() != k))
    throw Error("online learning: the saved state's matrices disagree in size");
  if (!state.dictionary.allFinite() || !state.a.allFinite() || !state.b.allFinite())
    throw Error("online learning: the saved state holds NaN or Inf");
  const std::mt19937_64 rng = detail::generatorFromText(state.rng, "online learning");
  dictionary_ = state.dictionary;
  a_ = state.a;
  b_ = state.b;
  seen_ = static_cast<std::size_t>(state.seen);
  steps_ = static_cast<std::size_t>(state.steps);
  rng_ = rng;
}

void OnlineDictionaryLearner::fit(const Eigen::MatrixXd& signals, const ObservationMask& mask, int epochs)
{
  detail::checkTrainingData(signals, mask, parameters_.num_atoms, parameters_.sparsity);
  std::vector<Eigen::Index> order(static_cast<std::size_t>(signals.cols()));
  const Eigen::Index batch_size = parameters_.batch_size;
  for (int epoch = 0; epoch < epochs; ++epoch) {
    std::iota(order.begin(), order.end(), 0);
    for (std::size_t i = order.size(); i > 1; --i)
      std::swap(order[i - 1], order[rng_() % i]);
    for (std::size_t start = 0; start < order.size(); start += static_cast<std::size_t>(batch_size)) {
      const std::size_t size = std::min(order.size() - start, static_cast<std::size_t>(batch_size));
      Eigen::MatrixXd batch(signals.rows(), static_cast<Eigen::Index>(size));
      ObservationMask batch_mask;
      if (mask.size() != 0)
        batch_mask.resize(mask.rows(), static_cast<Eigen::Index>(size));
      for (std::size_t i = 0; i < size; ++i) {
        batch.col(static_cast<Eigen::Index>(i)) = signals.col(order[start + i]);
        if (mask.size() != 0)
          batch_mask.col(static_cast<Eigen::Index>(i)) = mask.col(order[start + i]);
      }
      update(batch, batch_mask);
    }
  }
}

}  // namespace patchdict
}  // namespace pcl
