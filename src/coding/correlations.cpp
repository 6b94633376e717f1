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
int updateAndPickAvx2(const double* alpha0, const double* const* columns, const double* gamma, int size, int num_atoms,
                      const double* weight, double threshold, double* alpha);
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

int updateCorrelationsAndPick(const double* alpha0, const double* const* columns, const double* gamma, int size,
                              int num_atoms, const double* weight, double threshold, double* alpha)
{
#if defined(__x86_64__)
  if (correlationsUseAvx2())
    return updateAndPickAvx2(alpha0, columns, gamma, size, num_atoms, weight, threshold, alpha);
#endif
  int best = -1;
  double top = threshold;
  for (int k = 0; k < num_atoms; ++k) {
    double a = alpha0[k];
    for (int i = 0; i < size; ++i)
      a -= gamma[i] * columns[i][k];
    alpha[k] = a;
    const double value = (a < 0 ? -a : a) * weight[k];
    if (value > top) {
      top = value;
      best = k;
    }
  }
  return best;
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
