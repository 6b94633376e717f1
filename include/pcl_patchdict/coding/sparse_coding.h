// Sparse coding of signals over a dictionary of unit-norm atoms: Batch-OMP (Rubinstein, Zibulevsky
// & Elad 2008) with a precomputed Gram matrix, and masked OMP for signals with unobserved entries.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** When to stop adding atoms: after max_atoms, or once the squared residual norm (over the
  * observed entries) is at most the error budget — whichever comes first. The budget of a signal
  * is max(max_squared_error, max_squared_error_per_entry × its observed entries): a per-entry
  * target keeps the rms residual per entry the same for signals observed on fewer entries. */
struct SparseCodingParameters {
  int max_atoms = 8;
  double max_squared_error = 0.0;
  double max_squared_error_per_entry = 0.0;
};

/** Codes of many signals: one column per signal, atoms as rows (K × P). */
using SparseCodes = Eigen::SparseMatrix<double, Eigen::ColMajor, std::int64_t>;

/** \brief Batch-OMP of every column of `signals` (n × P) over `dictionary` (n × K, unit columns),
  * with gram = DᵀD precomputed once; parallel over signals. */
SparseCodes batchOMP(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& gram,
                     const Eigen::MatrixXd& signals, const SparseCodingParameters& parameters);

/** \brief Masked OMP: each signal is observed only where its mask column is true (n × P). Atoms are
  * selected by correlation with their column-normalised masked versions and fitted by least squares
  * on the observed rows; the code applies to the full dictionary, so D·code estimates the
  * unobserved entries too. Signals sharing a mask share one masked Gram matrix. */
SparseCodes maskedOMP(const Eigen::MatrixXd& dictionary, const Eigen::MatrixXd& signals,
                      const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& mask,
                      const SparseCodingParameters& parameters);

/** The SIMD kernels sparse coding runs here: "avx512", "avx2" (the same bits as "avx512") or
  * "portable" (no FMA: other bits). The widest the CPU has, unless the environment variable
  * PCL_PATCHDICT_SIMD (portable, avx2 or avx512; read once) narrows them — to reproduce another
  * machine's bits, say. Throws Error for a value that is unknown or more than the CPU has; every
  * coding call checks it before its parallel loops. */
std::string sparseCodingKernels();

/** Single-signal Batch-OMP on Dᵀx = correlations, xᵀx = signal_squared_norm. Appends the chosen
  * atoms and their coefficients; max_squared_error_per_entry does not apply (the signal's length
  * is not known here). Exposed for the learners and the tests. */
void batchOMPSingle(const Eigen::MatrixXd& gram, const Eigen::VectorXd& correlations, double signal_squared_norm,
                    const SparseCodingParameters& parameters, std::vector<int>& atoms,
                    std::vector<double>& coefficients);

}  // namespace patchdict
}  // namespace pcl
