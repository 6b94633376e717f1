// The dispatch of computeCorrelations, pickLargest, projectUpdateAndPick and subtractCombination:
// the AVX-512 kernels where the CPU has them, else the AVX2 + FMA ones (the same bits), else
// Eigen's product and plain loops; PCL_PATCHDICT_SIMD may narrow the choice.
#include "coding/correlations.h"

#include <pcl_patchdict/core/error.h>

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

#if defined(__x86_64__)
void correlationsAvx2(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, std::ptrdiff_t num_atoms,
                      const double* signals, std::ptrdiff_t signal_stride, std::ptrdiff_t num_signals, double* out,
                      std::ptrdiff_t out_stride);
void subtractCombinationAvx2(const double* g, const double* const* columns, const double* c, int count, int num_atoms,
                             double* out);
void subtractCombinationAvx512(const double* g, const double* const* columns, const double* c, int count,
                               int num_atoms, double* out);
int pickLargestAvx2(const double* alpha, const double* weight, int num_atoms, double threshold);
int projectUpdateAndPickAvx2(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                             double scale, double z, int num_atoms, const double* weight, double threshold, double* u,
                             double* alpha);
std::ptrdiff_t correlationsAvx512PanelSize(std::ptrdiff_t n, std::ptrdiff_t num_atoms);
void correlationsAvx512(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, std::ptrdiff_t num_atoms,
                        const double* signals, std::ptrdiff_t signal_stride, std::ptrdiff_t num_signals, double* out,
                        std::ptrdiff_t out_stride, double* panels);
int pickLargestAvx512(const double* alpha, const double* weight, int num_atoms, double threshold);
int projectUpdateAndPickAvx512(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                               double scale, double z, int num_atoms, const double* weight, double threshold,
                               double* u, double* alpha);
#endif

SimdKernels bestSimdKernels()
{
#if defined(__x86_64__) && defined(__GNUC__)
  // __builtin_cpu_supports also asks whether the operating system saves the wider registers.
  static const SimdKernels best = [] {
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma"))
      return SimdKernels::Portable;
    return __builtin_cpu_supports("avx512f") ? SimdKernels::Avx512 : SimdKernels::Avx2;
  }();
  return best;
#else
  return SimdKernels::Portable;
#endif
}

SimdKernels activeSimdKernels()
{
  // Read once; an unknown value fails every coding call with the same message.
  static const SimdKernels active = [] {
    const SimdKernels best = bestSimdKernels();
    const char* text = std::getenv("PCL_PATCHDICT_SIMD");
    if (text == nullptr || *text == '\0')
      return best;
    const std::string value(text);
    const SimdKernels asked = value == "portable" ? SimdKernels::Portable
                              : value == "avx2"   ? SimdKernels::Avx2
                              : value == "avx512" ? SimdKernels::Avx512
                                                  : throw Error("PCL_PATCHDICT_SIMD=" + value +
                                                                ": expected portable, avx2 or avx512");
    if (static_cast<int>(asked) > static_cast<int>(best))
      throw Error("PCL_PATCHDICT_SIMD=" + value + ": this CPU cannot run those kernels");
    return asked;
  }();
  return active;
}

namespace {

SimdKernels checked(SimdKernels kernels)
{
  if (static_cast<int>(kernels) > static_cast<int>(bestSimdKernels()))
    throw std::invalid_argument("correlations: this CPU cannot run the SIMD kernels asked for");
  return kernels;
}

}  // namespace

int pickLargest(const double* alpha, const double* weight, int num_atoms, double threshold)
{
  return pickLargest(alpha, weight, num_atoms, threshold, activeSimdKernels());
}

int pickLargest(const double* alpha, const double* weight, int num_atoms, double threshold, SimdKernels kernels)
{
#if defined(__x86_64__)
  switch (checked(kernels)) {
    case SimdKernels::Avx512: return pickLargestAvx512(alpha, weight, num_atoms, threshold);
    case SimdKernels::Avx2: return pickLargestAvx2(alpha, weight, num_atoms, threshold);
    case SimdKernels::Portable: break;
  }
#else
  checked(kernels);
#endif
  int best = -1;
  double top = threshold;
  for (int k = 0; k < num_atoms; ++k) {
    const double value = (alpha[k] < 0 ? -alpha[k] : alpha[k]) * weight[k];
    if (value > top) {
      top = value;
      best = k;
    }
  }
  return best;
}

int projectUpdateAndPick(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                         double scale, double z, int num_atoms, const double* weight, double threshold, double* u,
                         double* alpha)
{
  return projectUpdateAndPick(g, basis, stride, l, size, scale, z, num_atoms, weight, threshold, u, alpha,
                              activeSimdKernels());
}

int projectUpdateAndPick(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                         double scale, double z, int num_atoms, const double* weight, double threshold, double* u,
                         double* alpha, SimdKernels kernels)
{
#if defined(__x86_64__)
  switch (checked(kernels)) {
    case SimdKernels::Avx512:
      return projectUpdateAndPickAvx512(g, basis, stride, l, size, scale, z, num_atoms, weight, threshold, u, alpha);
    case SimdKernels::Avx2:
      return projectUpdateAndPickAvx2(g, basis, stride, l, size, scale, z, num_atoms, weight, threshold, u, alpha);
    case SimdKernels::Portable:
      break;
  }
#else
  checked(kernels);
#endif
  int best = -1;
  double top = threshold;
  for (int k = 0; k < num_atoms; ++k) {
    double v = g[k];
    for (int i = 0; i < size; ++i)
      v -= l[i] * basis[i * stride + k];
    v *= scale;
    u[k] = v;
    const double a = alpha[k] - z * v;
    alpha[k] = a;
    const double value = (a < 0 ? -a : a) * weight[k];
    if (value > top) {
      top = value;
      best = k;
    }
  }
  return best;
}

void subtractCombination(const double* g, const double* const* columns, const double* c, int count, int num_atoms,
                         double* out)
{
  subtractCombination(g, columns, c, count, num_atoms, out, activeSimdKernels());
}

void subtractCombination(const double* g, const double* const* columns, const double* c, int count, int num_atoms,
                         double* out, SimdKernels kernels)
{
#if defined(__x86_64__)
  switch (checked(kernels)) {
    case SimdKernels::Avx512: subtractCombinationAvx512(g, columns, c, count, num_atoms, out); return;
    case SimdKernels::Avx2: subtractCombinationAvx2(g, columns, c, count, num_atoms, out); return;
    case SimdKernels::Portable: break;
  }
#else
  checked(kernels);
#endif
  for (int k = 0; k < num_atoms; ++k) {
    double v = g == nullptr ? 0.0 : g[k];
    for (int i = 0; i < count; ++i)
      v -= c[i] * columns[i][k];
    out[k] = v;
  }
}

void computeCorrelations(const Eigen::MatrixXd& dictionary, const Eigen::Ref<const Eigen::MatrixXd>& signals,
                         Eigen::MatrixXd& out)
{
  computeCorrelations(dictionary, signals, out, activeSimdKernels());
}

void computeCorrelations(const Eigen::MatrixXd& dictionary, const Eigen::Ref<const Eigen::MatrixXd>& signals,
                         Eigen::MatrixXd& out, SimdKernels kernels)
{
  checked(kernels);
  out.resize(dictionary.cols(), signals.cols());
#if defined(__x86_64__)
  if (kernels == SimdKernels::Avx512 && dictionary.rows() > 0) {
    // The kernel's packed atom panels: scratch of this thread, 64-byte aligned for its loads.
    thread_local std::vector<double> scratch;
    const std::size_t size = static_cast<std::size_t>(correlationsAvx512PanelSize(dictionary.rows(), dictionary.cols()));
    if (scratch.size() < size + 8)
      scratch.resize(size + 8);
    void* start = scratch.data();
    std::size_t space = scratch.size() * sizeof(double);
    double* panels = static_cast<double*>(std::align(64, size * sizeof(double), start, space));
    correlationsAvx512(dictionary.data(), dictionary.outerStride(), dictionary.rows(), dictionary.cols(),
                       signals.data(), signals.outerStride(), signals.cols(), out.data(), out.outerStride(), panels);
    return;
  }
  if (kernels == SimdKernels::Avx2 && dictionary.rows() > 0) {
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
