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

/** True when computeCorrelations runs the AVX2 kernel on this CPU. */
bool correlationsUseAvx2();

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
