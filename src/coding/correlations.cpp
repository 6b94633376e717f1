// computeCorrelations: the AVX2 kernel when the CPU has AVX2 and FMA, Eigen's product otherwise.
#include "coding/correlations.h"

#include <cstddef>

namespace pcl {
namespace patchdict {
namespace detail {

#if defined(__x86_64__)
void correlationsAvx2(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, std::ptrdiff_t num_atoms,
                      const double* signals, std::ptrdiff_t signal_stride, std::ptrdiff_t num_signals, double* out,
                      std::ptrdiff_t out_stride);
#endif

bool correlationsUseAvx2()
{
#if defined(__x86_64__) && defined(__GNUC__)
  static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return available;
#else
  return false;
#endif
}

void computeCorrelations(const Eigen::MatrixXd& dictionary, const Eigen::Ref<const Eigen::MatrixXd>& signals,
                         Eigen::MatrixXd& out)
{
  out.resize(dictionary.cols(), signals.cols());
#if defined(__x86_64__)
  if (correlationsUseAvx2() && dictionary.rows() > 0) {
    correlationsAvx2(dictionary.data(), dictionary.outerStride(), dictionary.rows(), dictionary.cols(), signals.data(),
                     signals.outerStride(), signals.cols(), out.data(), out.outerStride());
    return;
  }
#endif
  out.noalias() = dictionary.transpose() * signals;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
