// Dictionary learning for sparse patch coding: K-SVD with the approximate atom update (Aharon et al.
// 2006; Rubinstein et al. 2008) for local dictionaries, and online learning (Mairal et al. 2009) for
// large or streamed patch sets. Both accept a mask of observed entries (training on damaged shapes).
#pragma once

#include <pcl_patchdict/core/observation_mask.h>

#include <pcl_patchdict/coding/sparse_coding.h>

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

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
  * they enter the statistics (an EM step).
  *
  * Everything the learner knows is its State (dictionary D, the statistics A = Σ α αᵀ and
  * B = Σ x αᵀ, counters, generator): state() / setState() make a run resumable bit for bit
  * (`learn --checkpoint`). A and B are sums over the signals (weighted by the mini-batch
  * forgetting factor), which is what makes the method distributable: shards coded against a
  * common D give statistics that add up, and one step on their sum (codeShard() on every shard,
  * applyRound() on the sums) is the step on the union — how `learn` runs on MPI ranks
  * (docs/design.md, "Across machines"). */
class OnlineDictionaryLearner {
public:
  /** The whole learner, as `learn --checkpoint` stores it. `rng` is the generator's state in the
    * standard's text form (operator<< of std::mt19937_64), portable between builds. */
  struct State {
    OnlineLearningParameters parameters;
    Eigen::MatrixXd dictionary;  ///< n × K (empty before the first update)
    Eigen::MatrixXd a;           ///< K × K
    Eigen::MatrixXd b;           ///< n × K
    std::uint64_t seen = 0;
    std::uint64_t steps = 0;
    std::string rng;
  };

  explicit OnlineDictionaryLearner(const OnlineLearningParameters& parameters);

  /** Feeds one mini-batch (n × b; mask empty or n × b). The first call fixes n and initialises the
    * atoms from the batch's signals. The same as initialise() (first call), codeShard() and
    * applyRound() on one shard. */
  void update(const Eigen::MatrixXd& batch, const ObservationMask& mask = ObservationMask());

  /** One shard's part of a mini-batch round, coded against the common dictionary. */
  struct ShardStatistics {
    Eigen::MatrixXd a;       ///< K × K: Σ α αᵀ over the shard's signals
    Eigen::MatrixXd b;       ///< n × K: Σ x αᵀ (unobserved entries of x predicted by D α)
    Eigen::MatrixXd filled;  ///< n × m: the shard's signals with those predictions (restart candidates)
  };
  /** A mini-batch split into shards (processes, machines): every shard is coded by codeShard()
    * against the same dictionary, the statistics are summed, and every holder of the learner
    * calls applyRound() with the sums, so all of them take the update one learner would take on
    * the combined batch. initialise() fixes n and the first atoms from the round's combined
    * signals (before the first round only). */
  bool initialised() const { return dictionary_.size() != 0; }
  void initialise(const Eigen::MatrixXd& batch, const ObservationMask& mask = ObservationMask());
  ShardStatistics codeShard(const Eigen::MatrixXd& batch, const ObservationMask& mask = ObservationMask()) const;
  /** Folds the summed statistics of a round of `signals` signals in (the mini-batch forgetting
    * factor of that size) and takes one atom pass. An atom nobody uses restarts from the
    * combined batch's column p, asked of `restart_column(p)` (p drawn from the learner's
    * generator; every holder asks for the same p in the same order). */
  void applyRound(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, Eigen::Index signals,
                  const std::function<Eigen::VectorXd(Eigen::Index)>& restart_column);
  /** Convenience: shuffled passes over an in-memory set, `epochs` times. */
  void fit(const Eigen::MatrixXd& signals, const ObservationMask& mask, int epochs);

  const Eigen::MatrixXd& dictionary() const { return dictionary_; }
  std::size_t signalsSeen() const { return seen_; }
  const OnlineLearningParameters& parameters() const { return parameters_; }

  State state() const;
  /** Replaces the learner with a saved one. Throws Error (one line) if the parameters differ from
    * this learner's, the sizes disagree (D n × K, A K × K, B n × K), a value is not finite, or
    * the generator text does not parse. */
  void setState(const State& state);
  /** One block-coordinate pass over the atoms on the current A and B (Mairal et al. 2009, alg. 2),
    * as update() ends with; for statistics summed from shards (see the class comment). Atoms with
    * A(j, j) ≈ 0 are left as they are. */
  void updateAtoms();

private:
  /** The atom pass; an unused atom restarts from column p (of `columns` drawn) if a source is given. */
  void blockCoordinateUpdate(Eigen::Index columns, const std::function<Eigen::VectorXd(Eigen::Index)>* restart_column);

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
