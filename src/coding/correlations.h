// Correlations C = DᵀX of signals with a dictionary's atoms, the product Batch-OMP starts from, and
// Batch-OMP's fused update: hand-written AVX-512 or AVX2 + FMA kernels (the same bits; chosen at run
// time, the build itself targets plain x86-64), Eigen's product and plain loops elsewhere.
#pragma once

#include <Eigen/Core>

namespace pcl {
namespace patchdict {
namespace detail {

/** The kernels a call may run: the AVX-512 and the AVX2 kernels sum in the same order (the same
  * bits); the portable code does not use FMA (other bits). */
enum class SimdKernels { Portable = 0, Avx2 = 1, Avx512 = 2 };

/** The widest kernels this CPU (and its operating system) can run. */
SimdKernels bestSimdKernels();

/** out = dictionaryᵀ · signals (K × P). With the AVX2 kernel every entry is one dot product summed
  * in a fixed order (four lanes over the rows, then the lanes pairwise, then the leftover rows),
  * whatever the blocking or the batch it is in; Eigen's product gives the same bits for the same
  * batch. Either way the thread count never enters. */
void computeCorrelations(const Eigen::MatrixXd& dictionary, const Eigen::Ref<const Eigen::MatrixXd>& signals,
                         Eigen::MatrixXd& out);
/** The same with the kernels named (no wider than bestSimdKernels(), else std::invalid_argument):
  * what the tests compare. */
void computeCorrelations(const Eigen::MatrixXd& dictionary, const Eigen::Ref<const Eigen::MatrixXd>& signals,
                         Eigen::MatrixXd& out, SimdKernels kernels);

/** One Batch-OMP step over a precomputed Gram matrix: alpha = alpha0 − Σ_i gamma(i)·columns[i]
  * (the chosen atoms' Gram columns, summed in order i), and the index of the first largest
  * weight(k)·|alpha(k)| above `threshold` (weight 0 excludes an atom), or −1. AVX-512 or AVX2 + FMA where
  * computeCorrelations uses them, plain loops (the same order, without FMA) elsewhere. */
int updateCorrelationsAndPick(const double* alpha0, const double* const* columns, const double* gamma, int size,
                              int num_atoms, const double* weight, double threshold, double* alpha);
int updateCorrelationsAndPick(const double* alpha0, const double* const* columns, const double* gamma, int size,
                              int num_atoms, const double* weight, double threshold, double* alpha,
                              SimdKernels kernels);

/** True when computeCorrelations runs the AVX2 or AVX-512 kernel on this CPU. */
bool correlationsUseAvx2();

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
