// Correlations C = DᵀX of signals with a dictionary's atoms, the product Batch-OMP starts from:
// a hand-written AVX2 + FMA kernel where the CPU has them (chosen at run time; the build itself
// targets plain x86-64), Eigen's product elsewhere.
#pragma once

#include <Eigen/Core>

namespace pcl {
namespace patchdict {
namespace detail {

/** out = dictionaryᵀ · signals (K × P). With the AVX2 kernel every entry is one dot product summed
  * in a fixed order (four lanes over the rows, then the lanes pairwise, then the leftover rows),
  * whatever the blocking or the batch it is in; Eigen's product gives the same bits for the same
  * batch. Either way the thread count never enters. */
void computeCorrelations(const Eigen::MatrixXd& dictionary, const Eigen::Ref<const Eigen::MatrixXd>& signals,
                         Eigen::MatrixXd& out);

/** One Batch-OMP step over a precomputed Gram matrix: alpha = alpha0 − Σ_i gamma(i)·columns[i]
  * (the chosen atoms' Gram columns, summed in order i), and the index of the first largest
  * weight(k)·|alpha(k)| above `threshold` (weight 0 excludes an atom), or −1. AVX2 + FMA where
  * computeCorrelations uses them, plain loops (the same order, without FMA) elsewhere. */
int updateCorrelationsAndPick(const double* alpha0, const double* const* columns, const double* gamma, int size,
                              int num_atoms, const double* weight, double threshold, double* alpha);

/** True when computeCorrelations runs the AVX2 kernel on this CPU. */
bool correlationsUseAvx2();

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
