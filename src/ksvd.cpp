// K-SVD (Aharon, Elad & Bruckstein, IEEE TSP 2006) with the approximate atom update of Rubinstein,
// Zibulevsky & Elad (2008): one power-iteration step d ← E·g/‖E·g‖, g ← Eᵀd instead of an SVD.
// With a mask the rank-1 step becomes one alternating least-squares step over the observed entries.
#include "learning_common.h"

#include <pcl_patchdict/error.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pcl {
namespace patchdict {

namespace {

struct Use {
  Eigen::Index signal;
  double coefficient;
};

}  // namespace

Eigen::MatrixXd learnKSVD(const Eigen::MatrixXd& signals, const ObservationMask& mask,
                          const KSVDParameters& parameters, LearningReport* report)
{
  detail::checkTrainingData(signals, mask, parameters.num_atoms, parameters.sparsity);
  if (parameters.iterations < 0)
    throw Error("K-SVD: the number of iterations must not be negative");
  const bool masked = mask.size() != 0;
  const Eigen::Index n = signals.rows(), count = signals.cols();
  const int num_atoms = parameters.num_atoms;
  std::mt19937_64 rng(parameters.seed);
  Eigen::MatrixXd dictionary = detail::initialAtoms(signals, mask, num_atoms, rng);
  if (report)
    *report = LearningReport();
  const double observed_total = masked ? static_cast<double>(mask.count()) : static_cast<double>(signals.size());
  // The mask as 0/1 doubles: the masked updates become vectorised products.
  const Eigen::MatrixXd observed = masked ? Eigen::MatrixXd(mask.cast<double>()) : Eigen::MatrixXd();

  for (int iteration = 0; iteration < parameters.iterations; ++iteration) {
    const SparseCodes codes = detail::codeSignals(dictionary, signals, mask, parameters.sparsity);
    // Residual over the observed entries, kept up to date through the atom updates.
    Eigen::MatrixXd residual = signals - dictionary * codes;
    if (masked)
      residual = residual.cwiseProduct(observed);
    if (report)
      report->rmse_per_iteration.push_back(std::sqrt(residual.squaredNorm() / std::max(observed_total, 1.0)));

    std::vector<std::vector<Use>> users(static_cast<std::size_t>(num_atoms));
    for (Eigen::Index p = 0; p < count; ++p)
      for (SparseCodes::InnerIterator it(codes, p); it; ++it)
        users[static_cast<std::size_t>(it.row())].push_back({p, it.value()});

    // Replacement candidates: the worst-represented signals, each used at most once per iteration.
    std::vector<Eigen::Index> worst(static_cast<std::size_t>(count));
    std::iota(worst.begin(), worst.end(), 0);
    const Eigen::VectorXd errors = residual.colwise().squaredNorm();
    std::stable_sort(worst.begin(), worst.end(), [&](Eigen::Index a, Eigen::Index b) { return errors[a] > errors[b]; });
    std::size_t next_worst = 0;
    auto replace = [&](int k) {
      while (next_worst < worst.size()) {
        Eigen::VectorXd candidate = detail::observedColumn(signals, mask, worst[next_worst++]);
        const double norm = candidate.norm();
        if (norm > 1e-12) {
          dictionary.col(k) = candidate / norm;
          if (report)
            ++report->atoms_replaced;
          return;
        }
      }
    };

    for (int k = 0; k < num_atoms; ++k) {
      auto& list = users[static_cast<std::size_t>(k)];
      if (list.empty()) {
        replace(k);
        continue;
      }
      // E_R = residual of the users with atom k's own contribution added back.
      for (const Use& use : list) {
        if (masked)
          residual.col(use.signal) += use.coefficient * dictionary.col(k).cwiseProduct(observed.col(use.signal));
        else
          residual.col(use.signal) += use.coefficient * dictionary.col(k);
      }
      Eigen::VectorXd atom = Eigen::VectorXd::Zero(n);
      if (!masked) {
        for (const Use& use : list)
          atom += use.coefficient * residual.col(use.signal);
      } else {
        // Row-wise least squares: d_j = Σ g_p E_jp / Σ g_p² over the users that observe row j.
        Eigen::VectorXd weight = Eigen::VectorXd::Zero(n);
        for (const Use& use : list) {
          atom += use.coefficient * residual.col(use.signal);
          weight += (use.coefficient * use.coefficient) * observed.col(use.signal);
        }
        for (Eigen::Index r = 0; r < n; ++r)
          atom[r] = weight[r] > 0.0 ? atom[r] / weight[r] : dictionary(r, k);
      }
      const double norm = atom.norm();
      if (!(norm > 1e-12)) {
        replace(k);
        continue;
      }
      atom /= norm;
      for (Use& use : list) {
        auto column = residual.col(use.signal);
        if (!masked) {
          use.coefficient = column.dot(atom);
          column -= use.coefficient * atom;
        } else {
          // The residual is zero where unobserved, so column·atom only sums observed rows.
          const double energy = atom.cwiseAbs2().dot(observed.col(use.signal));
          use.coefficient = energy > 1e-12 ? column.dot(atom) / energy : 0.0;
          column -= use.coefficient * atom.cwiseProduct(observed.col(use.signal));
        }
      }
      dictionary.col(k) = atom;
    }

    // Near-duplicate atoms waste capacity: give them to badly represented signals.
    for (int k = 1; k < num_atoms; ++k)
      for (int j = 0; j < k; ++j)
        if (std::abs(dictionary.col(k).dot(dictionary.col(j))) > parameters.max_coherence) {
          replace(k);
          break;
        }
  }
  return dictionary;
}

}  // namespace patchdict
}  // namespace pcl
