// K-SVD (Aharon, Elad & Bruckstein, IEEE TSP 2006) with the approximate atom update of Rubinstein,
// Zibulevsky & Elad (2008): one power-iteration step d ← E·g/‖E·g‖, g ← Eᵀd instead of an SVD.
// With a mask the rank-1 step becomes one alternating least-squares step over the observed entries.
#include "coding/learning_common.h"

#include <pcl_patchdict/core/error.h>

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

// Full data: the approximate atom update without forming the residual (Rubinstein et al. 2008):
// with E_i = x_i − Σ_{j≠k} γ_ji d_j for the users i of atom k,
//   d ∝ Σ_i g_i E_i = X_R g − D·w,  w = Σ_i g_i Σ_{j≠k} γ_ji e_j,   then   g_i ← E_i·d = x_i·d − Σ_{j≠k} γ_ji (Dᵀd)_j.
// Two read-only passes over the users' signals instead of five read/write passes over a residual
// as large as the training set (measured: 31 s → see bench/README.md for 50 000 patches).
template <typename Replace>
void updateAtomsWithoutResidual(const Eigen::MatrixXd& signals, SparseCodes& codes, Eigen::MatrixXd& dictionary,
                                Replace& replace)
{
  struct Slot {
    Eigen::Index signal, value;  // value: index into codes' value array
  };
  const Eigen::Index num_atoms = dictionary.cols(), n = dictionary.rows();
  std::vector<std::vector<Slot>> users(static_cast<std::size_t>(num_atoms));
  const auto* outer = codes.outerIndexPtr();
  const auto* inner = codes.innerIndexPtr();
  double* values = codes.valuePtr();
  for (Eigen::Index p = 0; p < codes.outerSize(); ++p)
    for (auto idx = outer[p]; idx < outer[p + 1]; ++idx)
      users[static_cast<std::size_t>(inner[idx])].push_back({p, idx});

  Eigen::VectorXd v(n), w(num_atoms), atom(n), u(num_atoms);
  for (Eigen::Index k = 0; k < num_atoms; ++k) {
    const auto& list = users[static_cast<std::size_t>(k)];
    if (list.empty()) {
      replace(static_cast<int>(k));
      continue;
    }
    v.setZero();
    w.setZero();
    for (const Slot& slot : list) {
      const double g = values[slot.value];
      v.noalias() += g * signals.col(slot.signal);
      for (auto idx = outer[slot.signal]; idx < outer[slot.signal + 1]; ++idx)
        if (inner[idx] != k)
          w[inner[idx]] += g * values[idx];
    }
    atom.noalias() = v - dictionary * w;
    const double norm = atom.norm();
    if (!(norm > 1e-12)) {
      for (const Slot& slot : list)
        values[slot.value] = 0.0;  // the atom explains nothing for them any more
      replace(static_cast<int>(k));
      continue;
    }
    atom /= norm;
    u.noalias() = dictionary.transpose() * atom;
    for (const Slot& slot : list) {
      double g = signals.col(slot.signal).dot(atom);
      for (auto idx = outer[slot.signal]; idx < outer[slot.signal + 1]; ++idx)
        if (inner[idx] != k)
          g -= values[idx] * u[inner[idx]];
      values[slot.value] = g;
    }
    dictionary.col(k) = atom;
  }
}

// With a mask: the residual over the observed entries is kept, and the rank-1 step becomes one
// alternating least-squares step (row-wise for the atom, per signal for its coefficient).
template <typename Replace>
void updateAtomsMasked(const Eigen::MatrixXd& observed, std::vector<std::vector<Use>>& users, Eigen::MatrixXd& residual,
                       Eigen::MatrixXd& dictionary, Replace& replace)
{
  const Eigen::Index n = dictionary.rows();
  for (Eigen::Index k = 0; k < dictionary.cols(); ++k) {
    auto& list = users[static_cast<std::size_t>(k)];
    if (list.empty()) {
      replace(static_cast<int>(k));
      continue;
    }
    // E_R = residual of the users with atom k's own contribution added back.
    for (const Use& use : list)
      residual.col(use.signal) += use.coefficient * dictionary.col(k).cwiseProduct(observed.col(use.signal));
    // Row-wise least squares: d_j = Σ g_p E_jp / Σ g_p² over the users that observe row j.
    Eigen::VectorXd atom = Eigen::VectorXd::Zero(n), weight = Eigen::VectorXd::Zero(n);
    for (const Use& use : list) {
      atom += use.coefficient * residual.col(use.signal);
      weight += (use.coefficient * use.coefficient) * observed.col(use.signal);
    }
    for (Eigen::Index r = 0; r < n; ++r)
      atom[r] = weight[r] > 0.0 ? atom[r] / weight[r] : dictionary(r, k);
    const double norm = atom.norm();
    if (!(norm > 1e-12)) {
      replace(static_cast<int>(k));
      continue;
    }
    atom /= norm;
    for (Use& use : list) {
      auto column = residual.col(use.signal);
      // The residual is zero where unobserved, so column·atom only sums observed rows.
      const double energy = atom.cwiseAbs2().dot(observed.col(use.signal));
      use.coefficient = energy > 1e-12 ? column.dot(atom) / energy : 0.0;
      column -= use.coefficient * atom.cwiseProduct(observed.col(use.signal));
    }
    dictionary.col(k) = atom;
  }
}

}  // namespace

Eigen::MatrixXd learnKSVD(const Eigen::MatrixXd& signals, const ObservationMask& mask,
                          const KSVDParameters& parameters, LearningReport* report)
{
  detail::checkTrainingData(signals, mask, parameters.num_atoms, parameters.sparsity);
  if (parameters.iterations < 0)
    throw Error("K-SVD: the number of iterations must not be negative");
  const bool masked = mask.size() != 0;
  const Eigen::Index count = signals.cols();
  const int num_atoms = parameters.num_atoms;
  std::mt19937_64 rng(parameters.seed);
  Eigen::MatrixXd dictionary = detail::initialAtoms(signals, mask, num_atoms, rng);
  if (report)
    *report = LearningReport();
  const double observed_total = masked ? static_cast<double>(mask.count()) : static_cast<double>(signals.size());
  // The mask as 0/1 doubles: the masked updates become vectorised products.
  const Eigen::MatrixXd observed = masked ? Eigen::MatrixXd(mask.cast<double>()) : Eigen::MatrixXd();

  for (int iteration = 0; iteration < parameters.iterations; ++iteration) {
    SparseCodes codes = detail::codeSignals(dictionary, signals, mask, parameters.sparsity);

    // Replacement candidates: the worst-represented signals, each used at most once per iteration.
    Eigen::VectorXd errors(count);
    Eigen::MatrixXd residual;  // the masked path keeps the whole residual up to date
    if (masked) {
      residual = (signals - dictionary * codes).cwiseProduct(observed);
      errors = residual.colwise().squaredNorm().transpose();
    } else {
      constexpr Eigen::Index block = 4096;  // per-signal errors without a P-column temporary
      for (Eigen::Index start = 0; start < count; start += block) {
        const Eigen::Index size = std::min(block, count - start);
        const Eigen::MatrixXd part = signals.middleCols(start, size) - dictionary * codes.middleCols(start, size);
        errors.segment(start, size) = part.colwise().squaredNorm().transpose();
      }
    }
    if (report)
      report->rmse_per_iteration.push_back(std::sqrt(errors.sum() / std::max(observed_total, 1.0)));
    std::vector<Eigen::Index> worst(static_cast<std::size_t>(count));
    std::iota(worst.begin(), worst.end(), 0);
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

    if (!masked) {
      updateAtomsWithoutResidual(signals, codes, dictionary, replace);
    } else {
      std::vector<std::vector<Use>> users(static_cast<std::size_t>(num_atoms));
      for (Eigen::Index p = 0; p < count; ++p)
        for (SparseCodes::InnerIterator it(codes, p); it; ++it)
          users[static_cast<std::size_t>(it.row())].push_back({p, it.value()});
      updateAtomsMasked(observed, users, residual, dictionary, replace);
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
