// Correlations C = DᵀX of signals with a dictionary's atoms, the product Batch-OMP starts from, and
// Batch-OMP's fused step over the atoms: hand-written AVX-512 or AVX2 + FMA kernels (the same bits; chosen at run
// time, the build itself targets plain x86-64), Eigen's product and plain loops elsewhere.
#pragma once

#include <Eigen/Core>

#include <cstddef>

namespace pcl {
namespace patchdict {
namespace detail {

/** The kernels a call may run: the AVX-512 and the AVX2 kernels sum in the same order (the same
  * bits); the portable code does not use FMA (other bits). */
enum class SimdKernels { Portable = 0, Avx2 = 1, Avx512 = 2 };

/** The widest kernels this CPU (and its operating system) can run. */
SimdKernels bestSimdKernels();

/** The kernels the calls without a SimdKernels argument run: bestSimdKernels(), or narrower when
  * the environment variable PCL_PATCHDICT_SIMD says so (portable, avx2 or avx512; read once) —
  * e.g. portable on an AVX2 machine reproduces the bits of a machine without AVX2. An unknown or
  * unavailable value: Error. */
SimdKernels activeSimdKernels();

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

/** The first k of the largest weight(k)·|alpha(k)| above `threshold` (≥ 0, so that weight 0
  * excludes an atom), or −1: Batch-OMP's first choice. */
int pickLargest(const double* alpha, const double* weight, int num_atoms, double threshold);
int pickLargest(const double* alpha, const double* weight, int num_atoms, double threshold, SimdKernels kernels);

/** One step of Batch-OMP in its projected form. With U = G_I L⁻ᵀ (`basis`: its `size` columns,
  * `stride` apart) and l the new atom's row of the Cholesky factor L of G_II, the new column of U
  * is u = (g − U l) · scale (g: the new atom's Gram column, scale = 1 / its diagonal entry of L),
  * stored to `u`; then alpha −= z·u (z: the new entry of L⁻¹ α0_I), and the first k of the largest
  * weight(k)·|alpha(k)| above `threshold` is returned, or −1. Each entry is summed in order i; the
  * AVX-512 and AVX2 + FMA kernels give the same bits, the plain loops (no FMA) others. */
int projectUpdateAndPick(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                         double scale, double z, int num_atoms, const double* weight, double threshold, double* u,
                         double* alpha);
int projectUpdateAndPick(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                         double scale, double z, int num_atoms, const double* weight, double threshold, double* u,
                         double* alpha, SimdKernels kernels);

/** out(k) = g(k) − Σ_i c(i)·columns[i][k] for k < num_atoms (g null: 0 − …), summed in order i: a
  * Gram column made from a few rows of the dictionary (masked coding). The same bits from the
  * AVX-512 and AVX2 + FMA kernels, others from the plain loop. */
void subtractCombination(const double* g, const double* const* columns, const double* c, int count, int num_atoms,
                         double* out);
void subtractCombination(const double* g, const double* const* columns, const double* c, int count, int num_atoms,
                         double* out, SimdKernels kernels);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
