// Batch-OMP after Rubinstein, Zibulevsky & Elad, "Efficient implementation of the K-SVD algorithm
// using Batch Orthogonal Matching Pursuit", Technion CS-2008-08: the residual is never formed; the
// correlations are updated through Gram columns and the least-squares fit through a progressive
// Cholesky factor of G_II. Masked OMP runs the same kernel on the column-normalised observed rows.
#include <pcl_patchdict/error.h>
#include <pcl_patchdict/sparse_coding.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace pcl {
namespace patchdict {

namespace {

// Gram access for a precomputed G.
struct FullGram {
  const Eigen::MatrixXd& gram;
  const double* column(int k) { return gram.col(k).data(); }
};

// Gram columns computed when an atom is chosen: for signals whose mask nobody else shares, this
// costs S·n·K instead of n·K² for the whole masked Gram matrix.
struct LazyGram {
  const Eigen::MatrixXd& atoms;  // n_observed × K, normalised columns
  Eigen::MatrixXd cache;         // K × S
  int used = 0;
  LazyGram(const Eigen::MatrixXd& a, int max_atoms) : atoms(a), cache(a.cols(), max_atoms) {}
  const double* column(int k)
  {
    cache.col(used).noalias() = atoms.transpose() * atoms.col(k);
    return cache.col(used++).data();
  }
};

// The Batch-OMP iteration (Rubinstein et al. 2008, Algorithm 5), with error and sparsity stopping.
// `usable` excludes atoms (masked atoms with no energy on the observed rows).
template <typename Gram>
void ompKernel(Gram& gram, const Eigen::VectorXd& alpha0, double signal_squared_norm,
               const SparseCodingParameters& parameters, const std::vector<char>* usable,
               std::vector<int>& atoms, std::vector<double>& coefficients)
{
  const int num_atoms = static_cast<int>(alpha0.size());
  const int max_atoms = std::min(parameters.max_atoms, num_atoms);
  atoms.clear();
  coefficients.clear();
  if (max_atoms <= 0)
    return;
  const bool error_stop = parameters.max_squared_error > 0.0;
  Eigen::MatrixXd lower = Eigen::MatrixXd::Zero(max_atoms, max_atoms);  // Cholesky factor of G_II
  Eigen::MatrixXd gram_selected(num_atoms, max_atoms);                   // G_{:,I}
  Eigen::VectorXd alpha = alpha0, gamma, beta, rhs(max_atoms);
  std::vector<char> selected(num_atoms, 0);
  double residual = signal_squared_norm, delta_previous = 0.0;
  // Correlations this small are round-off of an already exact fit.
  const double tiny = 1e-12 * std::sqrt(std::max(signal_squared_norm, 1e-300));

  for (int n = 0; n < max_atoms; ++n) {
    if (error_stop && residual <= parameters.max_squared_error)
      break;
    int best = -1;
    double best_value = tiny;
    for (int k = 0; k < num_atoms; ++k) {
      if (selected[k] || (usable && !(*usable)[k]))
        continue;
      const double value = std::abs(alpha[k]);
      if (value > best_value) {
        best_value = value;
        best = k;
      }
    }
    if (best < 0)
      break;
    const double* column = gram.column(best);
    if (n == 0) {
      lower(0, 0) = std::sqrt(column[best]);
    } else {
      Eigen::VectorXd w(n);
      for (int i = 0; i < n; ++i)
        w[i] = column[atoms[i]];
      lower.topLeftCorner(n, n).triangularView<Eigen::Lower>().solveInPlace(w);
      const double diagonal = column[best] - w.squaredNorm();
      if (diagonal <= 1e-10)  // the atom is (numerically) in the span of those chosen: stop
        break;
      lower.row(n).head(n) = w.transpose();
      lower(n, n) = std::sqrt(diagonal);
    }
    atoms.push_back(best);
    selected[best] = 1;
    gram_selected.col(n) = Eigen::Map<const Eigen::VectorXd>(column, num_atoms);
    const int size = n + 1;
    for (int i = 0; i < size; ++i)
      rhs[i] = alpha0[atoms[i]];
    gamma = rhs.head(size);
    const auto factor = lower.topLeftCorner(size, size);
    factor.triangularView<Eigen::Lower>().solveInPlace(gamma);
    factor.transpose().triangularView<Eigen::Upper>().solveInPlace(gamma);
    beta.noalias() = gram_selected.leftCols(size) * gamma;
    alpha = alpha0 - beta;
    if (error_stop) {
      double delta = 0.0;
      for (int i = 0; i < size; ++i)
        delta += gamma[i] * beta[atoms[i]];
      residual = residual - delta + delta_previous;
      delta_previous = delta;
    }
  }
  coefficients.assign(gamma.data(), gamma.data() + gamma.size());
  coefficients.resize(atoms.size());
}

void checkParameters(const SparseCodingParameters& parameters)
{
  if (parameters.max_atoms < 0)
    throw Error("sparse coding: the number of atoms per signal must not be negative");
  if (!(parameters.max_squared_error >= 0.0))
    throw Error("sparse coding: the error target must be a non-negative number");
}

SparseCodes assemble(Eigen::Index num_atoms, const std::vector<std::vector<int>>& atoms,
                     const std::vector<std::vector<double>>& coefficients)
{
  std::size_t nonzeros = 0;
  for (const auto& list : atoms)
    nonzeros += list.size();
  SparseCodes codes(num_atoms, static_cast<Eigen::Index>(atoms.size()));
  codes.reserve(static_cast<Eigen::Index>(nonzeros));
  for (std::size_t p = 0; p < atoms.size(); ++p) {
    std::vector<int> order(atoms[p].size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return atoms[p][a] < atoms[p][b]; });
    codes.startVec(static_cast<Eigen::Index>(p));
    for (const int i : order)
      codes.insertBack(atoms[p][i], static_cast<Eigen::Index>(p)) = coefficients[p][i];
  }
  codes.finalize();
  return codes;
}

}  // namespace

void batchOMPSingle(const Eigen::MatrixXd& gram, const Eigen::VectorXd& correlations, double signal_squared_norm,
                    const SparseCodingParameters& parameters, std::vector<int>& atoms,
                    std::vector<double>& coefficients)
{
  checkParameters(parameters);
  FullGram access{gram};
  ompKernel(access, correlations, signal_squared_norm, parameters, nullptr, atoms, coefficients);
}

SparseCodes batchOMP(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& gram, const Eigen::MatrixXd& signals,
                     const SparseCodingParameters& parameters)
{
  checkParameters(parameters);
  if (signals.rows() != dictionary.rows())
    throw Error("sparse coding: signals have " + std::to_string(signals.rows()) + " entries, atoms " +
                std::to_string(dictionary.rows()));
  if (gram.rows() != dictionary.cols() || gram.cols() != dictionary.cols())
    throw Error("sparse coding: the Gram matrix does not match the dictionary");
  const Eigen::Index count = signals.cols();
  std::vector<std::vector<int>> atoms(static_cast<std::size_t>(count));
  std::vector<std::vector<double>> coefficients(static_cast<std::size_t>(count));
  // Correlations Dᵀx in blocks: one GEMM per block instead of one GEMV per signal.
  constexpr Eigen::Index block = 1024;
  for (Eigen::Index start = 0; start < count; start += block) {
    const Eigen::Index size = std::min(block, count - start);
    const Eigen::MatrixXd correlations = dictionary.transpose() * signals.middleCols(start, size);
#pragma omp parallel for schedule(dynamic, 16)
    for (Eigen::Index i = 0; i < size; ++i) {
      const Eigen::Index p = start + i;
      FullGram access{gram};
      ompKernel(access, correlations.col(i), signals.col(p).squaredNorm(), parameters, nullptr,
                atoms[static_cast<std::size_t>(p)], coefficients[static_cast<std::size_t>(p)]);
    }
  }
  return assemble(dictionary.cols(), atoms, coefficients);
}

SparseCodes maskedOMP(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& signals,
                      const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& mask,
                      const SparseCodingParameters& parameters)
{
  checkParameters(parameters);
  if (signals.rows() != dictionary.rows() || mask.rows() != signals.rows() || mask.cols() != signals.cols())
    throw Error("masked sparse coding: signals, mask and dictionary sizes do not match");
  const Eigen::Index count = signals.cols(), num_atoms = dictionary.cols();
  const int max_atoms = std::min<int>(parameters.max_atoms, static_cast<int>(num_atoms));

  // Group signals by mask; a group large enough to pay for n·K² shares one masked Gram matrix.
  std::map<std::vector<bool>, std::vector<Eigen::Index>> groups;
  for (Eigen::Index p = 0; p < count; ++p) {
    std::vector<bool> key(static_cast<std::size_t>(mask.rows()));
    for (Eigen::Index r = 0; r < mask.rows(); ++r)
      key[static_cast<std::size_t>(r)] = mask(r, p);
    groups[std::move(key)].push_back(p);
  }
  std::vector<const std::vector<bool>*> keys;
  std::vector<const std::vector<Eigen::Index>*> members;
  for (const auto& [key, list] : groups) {
    keys.push_back(&key);
    members.push_back(&list);
  }

  std::vector<std::vector<int>> atoms(static_cast<std::size_t>(count));
  std::vector<std::vector<double>> coefficients(static_cast<std::size_t>(count));
  const Eigen::Index shared_gram_threshold = std::max<Eigen::Index>(2, num_atoms / std::max(1, max_atoms));

#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t g = 0; g < static_cast<std::ptrdiff_t>(keys.size()); ++g) {
    const std::vector<bool>& key = *keys[g];
    std::vector<Eigen::Index> rows;
    for (std::size_t r = 0; r < key.size(); ++r)
      if (key[r])
        rows.push_back(static_cast<Eigen::Index>(r));
    if (rows.empty())
      continue;  // nothing observed: the code stays empty
    const auto observed_count = static_cast<Eigen::Index>(rows.size());
    Eigen::MatrixXd masked(observed_count, num_atoms);
    for (Eigen::Index i = 0; i < observed_count; ++i)
      masked.row(i) = dictionary.row(rows[i]);
    // Column-normalise so that selection compares directions, not the atoms' leftover energy.
    Eigen::VectorXd norms = masked.colwise().norm();
    std::vector<char> usable(static_cast<std::size_t>(num_atoms), 1);
    for (Eigen::Index k = 0; k < num_atoms; ++k) {
      if (norms[k] > 1e-8) {
        masked.col(k) /= norms[k];
      } else {
        usable[static_cast<std::size_t>(k)] = 0;
        masked.col(k).setZero();
      }
    }
    const auto& list = *members[g];
    Eigen::MatrixXd gram;
    const bool shared = static_cast<Eigen::Index>(list.size()) >= shared_gram_threshold;
    if (shared)
      gram.noalias() = masked.transpose() * masked;
    Eigen::VectorXd observed(observed_count);
    for (const Eigen::Index p : list) {
      for (Eigen::Index i = 0; i < observed_count; ++i)
        observed[i] = signals(rows[i], p);
      const Eigen::VectorXd correlations = masked.transpose() * observed;
      auto& chosen = atoms[static_cast<std::size_t>(p)];
      auto& values = coefficients[static_cast<std::size_t>(p)];
      if (shared) {
        FullGram access{gram};
        ompKernel(access, correlations, observed.squaredNorm(), parameters, &usable, chosen, values);
      } else {
        LazyGram access(masked, std::max(1, max_atoms));
        ompKernel(access, correlations, observed.squaredNorm(), parameters, &usable, chosen, values);
      }
      for (std::size_t i = 0; i < chosen.size(); ++i)  // back to the un-normalised atoms
        values[i] /= norms[chosen[i]];
    }
  }
  return assemble(num_atoms, atoms, coefficients);
}

}  // namespace patchdict
}  // namespace pcl
