// Batch-OMP after Rubinstein, Zibulevsky & Elad, "Efficient implementation of the K-SVD algorithm
// using Batch Orthogonal Matching Pursuit", Technion CS-2008-08: the residual is never formed; the
// correlations are updated through Gram columns, made orthogonal over a progressive Cholesky factor
// of G_II (see ompKernel). Masked OMP runs the same kernel on the column-normalised observed rows.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/coding/sparse_coding.h>

#include "coding/correlations.h"

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

// Masked Gram columns computed only when an atom is chosen — for a signal whose mask nobody else
// shares this costs S·n·K at most, where the whole masked Gram matrix would cost n·K². Column k of
// the normalised masked Gram is s ⊙ Dᵀ(m ⊙ d_k) · s_k (s: inverse masked atom norms): the sum over
// the observed rows r of D_rk · D_r,:ᵀ, or, with fewer hidden rows, G_k minus the sum over those
// (detail::subtractCombination, AVX-512 or AVX2 where available).
struct LazyMaskedGram {
  const Eigen::MatrixXd& dictionary;             // n × K
  const Eigen::MatrixXd& gram;                   // DᵀD of the full dictionary
  const std::vector<Eigen::Index>& rows;         // the hidden rows (from_gram) or the observed ones
  const std::vector<const double*>& row_atoms;   // per row of `rows`, that row of D (a column of Dᵀ)
  bool from_gram;
  const Eigen::VectorXd& inverse_norms;
  Eigen::VectorXd& out;                          // K: the column, read only in its own step (ompKernel)
  std::vector<double>& weights;                  // scratch: ± D_rk over `rows`
  const double* column(int k)
  {
    const double* atom = dictionary.col(k).data();
    weights.resize(rows.size());
    for (std::size_t j = 0; j < rows.size(); ++j)
      weights[j] = from_gram ? atom[rows[j]] : -atom[rows[j]];
    detail::subtractCombination(from_gram ? gram.col(k).data() : nullptr, row_atoms.data(), weights.data(),
                                static_cast<int>(rows.size()), static_cast<int>(out.size()), out.data());
    out = out.cwiseProduct(inverse_norms) * inverse_norms[k];
    return out.data();
  }
};

// Buffers of one thread, reused across signals: allocation would otherwise cost as much as the
// arithmetic for small sparsities.
struct Workspace {
  std::vector<double> factor, inverse_diagonal, projected, gamma_flat, alpha_flat, weight, basis;
};

// Batch-OMP (Rubinstein, Zibulevsky & Elad 2008, Algorithm 5) in its projected form, with error and
// sparsity stopping, over Gram columns from `gram.column(k)` (a precomputed matrix, or masked
// columns made on demand); `usable` (K weights, 1 or 0; null: all 1) excludes atoms. With L the Cholesky factor of
// G_II, it keeps U = G_I L⁻ᵀ (K × |I|) and z = L⁻¹ α0_I instead of the coefficients:
//  - the new atom's row of L is its row of U, read off without a triangular solve;
//  - U's new column is (g − U l) / L_nn and α = α0 − U z shrinks by z_n times it, fused with the
//    next argmax in one pass (detail::projectUpdateAndPick: AVX-512 or AVX2 where available);
//  - the squared residual is ‖x‖² − ‖z‖²;
//  - the coefficients L⁻ᵀ z are solved once, at the end.
// The per-step triangular solves of the textbook form were chains of dependent divisions, half of
// the time outside the vector kernels at S = 20. Each column is needed in its own step only.
template <typename Gram>
void ompKernel(Gram& gram, const double* alpha0, Eigen::Index num_atoms_in, double signal_squared_norm,
               Eigen::Index entries, const SparseCodingParameters& parameters, const double* usable,
               Workspace& work, std::vector<int>& atoms, std::vector<double>& coefficients)
{
  const int num_atoms = static_cast<int>(num_atoms_in);
  const int max_atoms = std::min(parameters.max_atoms, num_atoms);
  atoms.clear();
  coefficients.clear();
  if (max_atoms <= 0)
    return;
  const double budget = std::max(parameters.max_squared_error,
                                 parameters.max_squared_error_per_entry * static_cast<double>(entries));
  const bool error_stop = budget > 0.0;
  const std::size_t s = static_cast<std::size_t>(max_atoms), k_count = static_cast<std::size_t>(num_atoms);
  work.factor.resize(s * s);
  work.inverse_diagonal.resize(s);
  work.projected.resize(s);
  work.gamma_flat.resize(s);
  work.alpha_flat.resize(k_count);
  work.weight.resize(k_count);
  work.basis.resize(k_count * s);
  if (usable == nullptr)
    std::fill(work.weight.begin(), work.weight.end(), 1.0);
  else
    std::copy(usable, usable + num_atoms, work.weight.begin());
  double* lower = work.factor.data();  // row i at i·s
  double* inverse = work.inverse_diagonal.data();
  double* z = work.projected.data();
  double* alpha = work.alpha_flat.data();
  double* weight = work.weight.data();
  double* basis = work.basis.data();  // U, column j at j·K
  std::copy(alpha0, alpha0 + num_atoms, alpha);
  double residual = signal_squared_norm;
  // Correlations this small are round-off of an already exact fit.
  const double tiny = 1e-12 * std::sqrt(std::max(signal_squared_norm, 1e-300));
  int size = 0;
  int best = detail::pickLargest(alpha, weight, num_atoms, tiny);
  while (size < max_atoms && best >= 0 && !(error_stop && residual <= budget)) {
    const int n = size;
    const double* column = gram.column(best);
    double* row = lower + static_cast<std::size_t>(n) * s;
    double diagonal = column[best];
    for (int j = 0; j < n; ++j) {
      row[j] = basis[static_cast<std::size_t>(j) * k_count + static_cast<std::size_t>(best)];
      diagonal -= row[j] * row[j];
    }
    if (n > 0 && diagonal <= 1e-10)  // the atom is (numerically) in the span of those chosen: stop
      break;
    row[n] = std::sqrt(diagonal);
    inverse[n] = 1.0 / row[n];
    z[n] = alpha[best] * inverse[n];
    residual -= z[n] * z[n];
    atoms.push_back(best);
    weight[best] = 0.0;
    size = n + 1;
    if (size == max_atoms || (error_stop && residual <= budget))
      break;  // nobody reads α again
    best = detail::projectUpdateAndPick(column, basis, static_cast<std::ptrdiff_t>(k_count), row, n, inverse[n], z[n],
                                        num_atoms, weight, tiny, basis + static_cast<std::size_t>(n) * k_count, alpha);
  }
  // Lᵀ γ = z.
  double* gamma = work.gamma_flat.data();
  for (int i = size - 1; i >= 0; --i) {
    double value = z[i];
    for (int j = i + 1; j < size; ++j)
      value -= lower[static_cast<std::size_t>(j) * s + static_cast<std::size_t>(i)] * gamma[j];
    gamma[i] = value * inverse[i];
  }
  coefficients.assign(gamma, gamma + size);
}

void checkParameters(const SparseCodingParameters& parameters)
{
  detail::activeSimdKernels();  // a bad PCL_PATCHDICT_SIMD fails here, not inside a parallel loop
  if (parameters.max_atoms < 0)
    throw Error("sparse coding: the number of atoms per signal must not be negative");
  if (!(parameters.max_squared_error >= 0.0) || !(parameters.max_squared_error_per_entry >= 0.0))
    throw Error("sparse coding: the error target must be a non-negative number");
}

/** Per signal its chosen atoms and their coefficients, in flat lists (signal p's at p × stride,
  * counts[p] of them): no allocation per signal. Threads write disjoint signals. */
struct CodeLists {
  CodeLists(Eigen::Index signals, Eigen::Index num_atoms, int max_atoms)
      : stride(static_cast<std::size_t>(std::max(0, std::min<int>(max_atoms, static_cast<int>(num_atoms))))),
        counts(static_cast<std::size_t>(signals), 0), atoms(static_cast<std::size_t>(signals) * stride),
        coefficients(atoms.size())
  {
  }
  void set(Eigen::Index p, const std::vector<int>& chosen, const std::vector<double>& values)
  {
    const auto at = static_cast<std::ptrdiff_t>(static_cast<std::size_t>(p) * stride);
    std::copy(chosen.begin(), chosen.end(), atoms.begin() + at);
    std::copy(values.begin(), values.end(), coefficients.begin() + at);
    counts[static_cast<std::size_t>(p)] = static_cast<int>(chosen.size());
  }
  /** The codes as a K × P sparse matrix, atoms in increasing order within a column. */
  SparseCodes assemble(Eigen::Index num_atoms) const
  {
    SparseCodes codes(num_atoms, static_cast<Eigen::Index>(counts.size()));
    codes.reserve(static_cast<Eigen::Index>(std::accumulate(counts.begin(), counts.end(), std::size_t{0})));
    std::vector<int> order;
    for (std::size_t p = 0; p < counts.size(); ++p) {
      const int* list = atoms.data() + p * stride;
      order.resize(static_cast<std::size_t>(counts[p]));
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](int a, int b) { return list[a] < list[b]; });
      codes.startVec(static_cast<Eigen::Index>(p));
      for (const int i : order)
        codes.insertBack(list[i], static_cast<Eigen::Index>(p)) = coefficients[p * stride + static_cast<std::size_t>(i)];
    }
    codes.finalize();
    return codes;
  }
  std::size_t stride;
  std::vector<int> counts, atoms;
  std::vector<double> coefficients;
};

}  // namespace

std::string sparseCodingKernels()
{
  switch (detail::activeSimdKernels()) {
    case detail::SimdKernels::Avx512: return "avx512";
    case detail::SimdKernels::Avx2: return "avx2";
    case detail::SimdKernels::Portable: break;
  }
  return "portable";
}

void batchOMPSingle(const Eigen::MatrixXd& gram, const Eigen::VectorXd& correlations, double signal_squared_norm,
                    const SparseCodingParameters& parameters, std::vector<int>& atoms,
                    std::vector<double>& coefficients)
{
  checkParameters(parameters);
  if (gram.rows() != correlations.size() || gram.cols() != correlations.size())
    throw Error("sparse coding: the Gram matrix does not match the correlations");
  Workspace work;
  FullGram access{gram};
  ompKernel(access, correlations.data(), correlations.size(), signal_squared_norm, 0, parameters, nullptr, work, atoms,
            coefficients);
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
  CodeLists codes(count, dictionary.cols(), parameters.max_atoms);
  // Correlations Dᵀx in blocks: one product per block instead of one per signal; 256 signals keep
  // the block small enough to stay in cache (and a first call's fresh pages few).
  constexpr Eigen::Index block = 256;
  Eigen::MatrixXd correlations;
  for (Eigen::Index start = 0; start < count; start += block) {
    const Eigen::Index size = std::min(block, count - start);
    detail::computeCorrelations(dictionary, signals.middleCols(start, size), correlations);
#pragma omp parallel
    {
      Workspace work;
      FullGram access{gram};
      std::vector<int> chosen;
      std::vector<double> values;
#pragma omp for schedule(dynamic, 16)
      for (Eigen::Index i = 0; i < size; ++i) {
        const Eigen::Index p = start + i;
        ompKernel(access, correlations.col(i).data(), gram.rows(), signals.col(p).squaredNorm(), signals.rows(),
                  parameters, nullptr, work, chosen, values);
        codes.set(p, chosen, values);
      }
    }
  }
  return codes.assemble(dictionary.cols());
}

namespace {

using Mask = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

/** Signals that share a mask with enough others (`threshold`) share one normalised masked Gram
  * matrix: groups of such signals by mask, and the others ("singles") in index order. */
void groupByMask(const Mask& mask, std::size_t threshold, std::map<std::vector<bool>, std::vector<Eigen::Index>>& groups,
                 std::vector<const std::vector<Eigen::Index>*>& shared_groups, std::vector<Eigen::Index>& singles)
{
  const Eigen::Index n = mask.rows();
  for (Eigen::Index p = 0; p < mask.cols(); ++p) {
    std::vector<bool> key(static_cast<std::size_t>(n));
    for (Eigen::Index r = 0; r < n; ++r)
      key[static_cast<std::size_t>(r)] = mask(r, p);
    groups[std::move(key)].push_back(p);
  }
  for (const auto& [key, list] : groups) {
    if (list.size() >= threshold)
      shared_groups.push_back(&list);
    else
      singles.insert(singles.end(), list.begin(), list.end());
  }
  std::sort(singles.begin(), singles.end());
}

/** Shared masks: the observed rows gathered, and the normalised masked Gram matrix formed, once
  * per group. */
void codeSharedMasks(const Eigen::MatrixXd& dictionary_t, const Eigen::MatrixXd& signals, const Mask& mask,
                     const std::vector<const std::vector<Eigen::Index>*>& shared_groups,
                     const SparseCodingParameters& parameters, CodeLists& codes)
{
  const Eigen::Index num_atoms = dictionary_t.rows(), n = dictionary_t.cols();
#pragma omp parallel
  {
    Workspace work;
    Eigen::MatrixXd masked_t, masked_atoms, gram, block, block_correlations;
    Eigen::VectorXd norms, inverse(num_atoms);
    std::vector<double> usable;
    std::vector<int> chosen;
    std::vector<double> values;
#pragma omp for schedule(dynamic, 1)
    for (std::ptrdiff_t g = 0; g < static_cast<std::ptrdiff_t>(shared_groups.size()); ++g) {
      const auto& list = *shared_groups[static_cast<std::size_t>(g)];
      std::vector<Eigen::Index> rows;
      for (Eigen::Index r = 0; r < n; ++r)
        if (mask(r, list.front()))
          rows.push_back(r);
      if (rows.empty())
        continue;  // nothing observed: the codes stay empty
      const auto observed_count = static_cast<Eigen::Index>(rows.size());
      masked_t.resize(num_atoms, observed_count);  // (M·D)ᵀ
      for (Eigen::Index i = 0; i < observed_count; ++i)
        masked_t.col(i) = dictionary_t.col(rows[i]);
      // Column-normalise the masked atoms so that selection compares directions, not the energy
      // each atom happens to keep on the observed rows.
      norms = masked_t.rowwise().norm();
      usable.resize(static_cast<std::size_t>(num_atoms));
      for (Eigen::Index k = 0; k < num_atoms; ++k) {
        usable[static_cast<std::size_t>(k)] = norms[k] > 1e-8 ? 1.0 : 0.0;
        inverse[k] = norms[k] > 1e-8 ? 1.0 / norms[k] : 0.0;
      }
      // Batch-OMP on the normalised masked atoms: correlations of the group's signals by the blocked
      // kernel, the fused steps over the masked Gram matrix. An atom with no energy on the observed
      // rows is a zero row there (inverse 0) and excluded by `usable`.
      masked_atoms = inverse.asDiagonal() * masked_t;  // K × m, unit rows (or zero)
      gram.noalias() = masked_atoms * masked_atoms.transpose();
      const Eigen::MatrixXd atoms_by_row = masked_atoms.transpose();  // m × K
      FullGram access{gram};
      for (std::size_t start = 0; start < list.size(); start += 256) {
        const std::size_t size = std::min<std::size_t>(256, list.size() - start);
        block.resize(observed_count, static_cast<Eigen::Index>(size));
        for (std::size_t j = 0; j < size; ++j)
          for (Eigen::Index i = 0; i < observed_count; ++i)
            block(i, static_cast<Eigen::Index>(j)) = signals(rows[static_cast<std::size_t>(i)], list[start + j]);
        detail::computeCorrelations(atoms_by_row, block, block_correlations);
        for (std::size_t j = 0; j < size; ++j) {
          const auto column = static_cast<Eigen::Index>(j);
          ompKernel(access, block_correlations.col(column).data(), num_atoms, block.col(column).squaredNorm(),
                    observed_count, parameters, usable.data(), work, chosen, values);
          for (std::size_t i = 0; i < chosen.size(); ++i)  // back to the un-normalised atoms
            values[i] *= inverse[chosen[i]];
          codes.set(list[start + j], chosen, values);
        }
      }
    }
  }
}

/** Masks of their own: correlations Dᵀ(m ⊙ x) and masked norms² (D ⊙ D)ᵀm for a block of signals
  * by the blocked correlation kernel, then Gram columns on demand. */
void codeSingleMasks(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& dictionary_t,
                     const Eigen::MatrixXd& signals, const Mask& mask, const std::vector<Eigen::Index>& singles,
                     const SparseCodingParameters& parameters, CodeLists& codes)
{
  const Eigen::Index num_atoms = dictionary.cols(), n = dictionary.rows();
  const Eigen::MatrixXd squared = dictionary.cwiseAbs2();
  const Eigen::MatrixXd full_gram = singles.empty() ? Eigen::MatrixXd() : Eigen::MatrixXd(dictionary_t * dictionary);
  constexpr std::size_t block = 1024;
  Eigen::MatrixXd block_signals, block_masks, correlations, squared_norms;
  for (std::size_t start = 0; start < singles.size(); start += block) {
    const auto size = static_cast<Eigen::Index>(std::min(block, singles.size() - start));
    block_signals.resize(n, size);
    block_masks.resize(n, size);
    for (Eigen::Index i = 0; i < size; ++i) {
      const Eigen::Index p = singles[start + static_cast<std::size_t>(i)];
      block_masks.col(i) = mask.col(p).cast<double>();
      block_signals.col(i) = signals.col(p).cwiseProduct(block_masks.col(i));
    }
    detail::computeCorrelations(dictionary, block_signals, correlations);
    detail::computeCorrelations(squared, block_masks, squared_norms);
#pragma omp parallel
    {
      Workspace work;
      Eigen::VectorXd inverse(num_atoms), alpha0, gram_column(num_atoms);
      std::vector<double> usable(static_cast<std::size_t>(num_atoms));
      std::vector<Eigen::Index> hidden, observed;
      std::vector<const double*> row_atoms;
      std::vector<double> weights;
      std::vector<int> chosen;
      std::vector<double> values;
#pragma omp for schedule(dynamic, 16)
      for (Eigen::Index i = 0; i < size; ++i) {
        const Eigen::Index p = singles[start + static_cast<std::size_t>(i)];
        for (Eigen::Index k = 0; k < num_atoms; ++k) {
          const double norm = std::sqrt(std::max(squared_norms(k, i), 0.0));
          usable[static_cast<std::size_t>(k)] = norm > 1e-8 ? 1.0 : 0.0;
          inverse[k] = norm > 1e-8 ? 1.0 / norm : 0.0;
        }
        hidden.clear();
        observed.clear();
        for (Eigen::Index r = 0; r < n; ++r)
          (block_masks(r, i) == 0.0 ? hidden : observed).push_back(r);
        const bool from_gram = 2 * hidden.size() < static_cast<std::size_t>(n);
        const std::vector<Eigen::Index>& rows = from_gram ? hidden : observed;
        row_atoms.clear();
        for (const Eigen::Index r : rows)
          row_atoms.push_back(dictionary_t.col(r).data());
        alpha0 = correlations.col(i).cwiseProduct(inverse);
        LazyMaskedGram access{dictionary, full_gram, rows, row_atoms, from_gram, inverse, gram_column, weights};
        ompKernel(access, alpha0.data(), num_atoms, block_signals.col(i).squaredNorm(),
                  n - static_cast<Eigen::Index>(hidden.size()),
                  parameters, usable.data(), work, chosen, values);
        for (std::size_t j = 0; j < chosen.size(); ++j)
          values[j] *= inverse[chosen[j]];
        codes.set(p, chosen, values);
      }
    }
  }
}

}  // namespace

SparseCodes maskedOMP(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& signals,
                      const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& mask,
                      const SparseCodingParameters& parameters)
{
  checkParameters(parameters);
  if (signals.rows() != dictionary.rows() || mask.rows() != signals.rows() || mask.cols() != signals.cols())
    throw Error("masked sparse coding: signals, mask and dictionary sizes do not match");
  const Eigen::Index count = signals.cols(), num_atoms = dictionary.cols();
  const int max_atoms = std::min<int>(parameters.max_atoms, static_cast<int>(num_atoms));
  CodeLists codes(count, num_atoms, max_atoms);
  const Eigen::MatrixXd dictionary_t = dictionary.transpose();

  std::map<std::vector<bool>, std::vector<Eigen::Index>> groups;
  std::vector<const std::vector<Eigen::Index>*> shared_groups;
  std::vector<Eigen::Index> singles;
  const auto shared_gram_threshold = static_cast<std::size_t>(std::max<Eigen::Index>(2, num_atoms / std::max(1, max_atoms)));
  groupByMask(mask, shared_gram_threshold, groups, shared_groups, singles);
  codeSharedMasks(dictionary_t, signals, mask, shared_groups, parameters, codes);
  codeSingleMasks(dictionary, dictionary_t, signals, mask, singles, parameters, codes);
  return codes.assemble(num_atoms);
}

}  // namespace patchdict
}  // namespace pcl
