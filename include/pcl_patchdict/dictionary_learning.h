// Dictionary learning for sparse patch coding: K-SVD with the approximate atom update (Aharon et al.
// 2006; Rubinstein et al. 2008) for local dictionaries, and online learning (Mairal et al. 2009) for
// large or streamed patch sets. Both accept a mask of observed entries (training on damaged shapes).
#pragma once

#include <pcl_patchdict/sparse_coding.h>

#include <Eigen/Core>

#include <cstdint>
#include <random>
#include <vector>

namespace pcl {
namespace patchdict {

using ObservationMask = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

struct KSVDParameters {
  int num_atoms = 100;
  int sparsity = 8;          ///< atoms per signal while learning
  int iterations = 20;
  std::uint64_t seed = 1;
  /** Atoms more coherent than this with an earlier atom are replaced by the worst-fit signal. */
  double max_coherence = 0.99;
};

/** What happened during learning: the RMS representation error (over observed entries) after
  * each iteration's coding step, and how many atoms were replaced. */
struct LearningReport {
  std::vector<double> rmse_per_iteration;
  std::size_t atoms_replaced = 0;
};

/** \brief K-SVD on the columns of `signals` (n × P). `mask` (n × P, or empty) marks observed entries;
  * unobserved ones are ignored in coding and in the atom updates. Initial atoms are distinct
  * signals drawn with the seed. Returns the n × K dictionary with unit columns. */
Eigen::MatrixXd learnKSVD(const Eigen::MatrixXd& signals, const ObservationMask& mask,
                          const KSVDParameters& parameters, LearningReport* report = nullptr);

struct OnlineLearningParameters {
  int num_atoms = 100;
  int sparsity = 8;
  int batch_size = 512;
  std::uint64_t seed = 1;
};

/** \brief Online dictionary learning (Mairal, Bach, Ponce & Sapiro, ICML 2009) with OMP coding:
  * memory is O(n·K + K² + batch), whatever the number of signals, so patches can be streamed from
  * many files. Unobserved entries of a batch are filled with the current reconstruction before
  * they enter the statistics (an EM step). */
class OnlineDictionaryLearner {
public:
  explicit OnlineDictionaryLearner(const OnlineLearningParameters& parameters);

  /** Feeds one mini-batch (n × b; mask empty or n × b). The first call fixes n and initialises the
    * atoms from the batch's signals. */
  void update(const Eigen::MatrixXd& batch, const ObservationMask& mask = ObservationMask());
  /** Convenience: shuffled passes over an in-memory set, `epochs` times. */
  void fit(const Eigen::MatrixXd& signals, const ObservationMask& mask, int epochs);

  const Eigen::MatrixXd& dictionary() const { return dictionary_; }
  std::size_t signalsSeen() const { return seen_; }

private:
  OnlineLearningParameters parameters_;
  Eigen::MatrixXd dictionary_;  // n × K, unit columns
  Eigen::MatrixXd a_;           // K × K: Σ α αᵀ (decayed)
  Eigen::MatrixXd b_;           // n × K: Σ x αᵀ (decayed)
  std::size_t seen_ = 0;
  std::size_t steps_ = 0;
  std::mt19937_64 rng_;
};

}  // namespace patchdict
}  // namespace pcl
