// The AVX2 + FMA kernels of computeCorrelations, pickLargest, projectUpdateAndPick and
// subtractCombination, in a file of its own compiled with -mavx2 -mfma.
// Nothing here is a template or an inline function of a header (no Eigen, no std::): a weak
// symbol compiled for AVX2 could otherwise be picked by the linker for the plain-x86-64 callers.
#include <immintrin.h>

#include <cstddef>

namespace pcl {
namespace patchdict {
namespace detail {

namespace {

/** Σ of four lanes, pairwise: (l0 + l1) + (l2 + l3). */
double laneSum(__m256d v)
{
  const __m128d low = _mm256_castpd256_pd128(v), high = _mm256_extractf128_pd(v, 1);
  const double l0 = _mm_cvtsd_f64(low), l1 = _mm_cvtsd_f64(_mm_unpackhi_pd(low, low));
  const double l2 = _mm_cvtsd_f64(high), l3 = _mm_cvtsd_f64(_mm_unpackhi_pd(high, high));
  return (l0 + l1) + (l2 + l3);
}

/** One dot product in the kernel's order: four lanes by FMA over rows 0 … 4⌊n/4⌋, the lanes
  * pairwise, then the leftover rows one by one. The blocks below keep exactly this order. */
double dot(const double* a, const double* b, std::ptrdiff_t n)
{
  const std::ptrdiff_t body = n & ~std::ptrdiff_t{3};
  __m256d sum = _mm256_setzero_pd();
  for (std::ptrdiff_t i = 0; i < body; i += 4)
    sum = _mm256_fmadd_pd(_mm256_loadu_pd(a + i), _mm256_loadu_pd(b + i), sum);
  double total = laneSum(sum);
  for (std::ptrdiff_t i = body; i < n; ++i)
    total = __builtin_fma(a[i], b[i], total);
  return total;
}

}  // namespace

double dotAvx2(const double* a, const double* b, std::ptrdiff_t n) { return dot(a, b, n); }

/** out(k, p) = Σ_i atoms(i, k) · signals(i, p), all column-major: atoms n × K (column stride
  * atom_stride), signals n × P (signal_stride), out K × P (out_stride). */
void correlationsAvx2(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, std::ptrdiff_t num_atoms,
                      const double* signals, std::ptrdiff_t signal_stride, std::ptrdiff_t num_signals, double* out,
                      std::ptrdiff_t out_stride)
{
  // Blocks of 4 atoms × 3 signals: 12 accumulators, 3 signal vectors and one atom vector fill the
  // 16 AVX registers without spilling (4 × 4 spilled and ran at two thirds of the speed).
  constexpr int kAtoms = 4, kSignals = 3;
  const std::ptrdiff_t body = n & ~std::ptrdiff_t{3};
  std::ptrdiff_t p = 0;
  for (; p + kSignals <= num_signals; p += kSignals) {
    const double* x[kSignals] = {signals + p * signal_stride, signals + (p + 1) * signal_stride,
                                 signals + (p + 2) * signal_stride};
    std::ptrdiff_t k = 0;
    for (; k + kAtoms <= num_atoms; k += kAtoms) {
      const double* d[kAtoms] = {atoms + k * atom_stride, atoms + (k + 1) * atom_stride,
                                 atoms + (k + 2) * atom_stride, atoms + (k + 3) * atom_stride};
      __m256d acc[kAtoms][kSignals];
      for (int a = 0; a < kAtoms; ++a)
        for (int s = 0; s < kSignals; ++s)
          acc[a][s] = _mm256_setzero_pd();
      for (std::ptrdiff_t i = 0; i < body; i += 4) {
        const __m256d x0 = _mm256_loadu_pd(x[0] + i), x1 = _mm256_loadu_pd(x[1] + i), x2 = _mm256_loadu_pd(x[2] + i);
        for (int a = 0; a < kAtoms; ++a) {
          const __m256d dv = _mm256_loadu_pd(d[a] + i);
          acc[a][0] = _mm256_fmadd_pd(dv, x0, acc[a][0]);
          acc[a][1] = _mm256_fmadd_pd(dv, x1, acc[a][1]);
          acc[a][2] = _mm256_fmadd_pd(dv, x2, acc[a][2]);
        }
      }
      for (int s = 0; s < kSignals; ++s)
        for (int a = 0; a < kAtoms; ++a) {
          double total = laneSum(acc[a][s]);
          for (std::ptrdiff_t i = body; i < n; ++i)
            total = __builtin_fma(d[a][i], x[s][i], total);
          out[(p + s) * out_stride + k + a] = total;
        }
    }
    for (; k < num_atoms; ++k)
      for (int s = 0; s < kSignals; ++s)
        out[(p + s) * out_stride + k] = dot(atoms + k * atom_stride, x[s], n);
  }
  for (; p < num_signals; ++p)
    for (std::ptrdiff_t k = 0; k < num_atoms; ++k)
      out[p * out_stride + k] = dot(atoms + k * atom_stride, signals + p * signal_stride, n);
}

namespace {

/** Per lane the first largest weight·|α| so far, and its atom. */
struct LaneMaxima {
  __m256d value, index;
  inline void offer(__m256d a, const double* weight, int k)
  {
    const __m256d v = _mm256_mul_pd(_mm256_andnot_pd(_mm256_set1_pd(-0.0), a), _mm256_loadu_pd(weight + k));
    const __m256d better = _mm256_cmp_pd(v, value, _CMP_GT_OQ);
    value = _mm256_blendv_pd(value, v, better);
    index = _mm256_blendv_pd(index, _mm256_add_pd(_mm256_set1_pd(static_cast<double>(k)),
                                                  _mm256_setr_pd(0.0, 1.0, 2.0, 3.0)), better);
  }
  /** The first largest over the lanes: equal maxima go to the smaller atom. */
  int first(double threshold, double& top) const
  {
    double values[4], indices[4];
    _mm256_storeu_pd(values, value);
    _mm256_storeu_pd(indices, index);
    top = threshold;
    int best = -1;
    for (int lane = 0; lane < 4; ++lane) {
      const int at = static_cast<int>(indices[lane]);
      if (at >= 0 && (values[lane] > top || (values[lane] == top && (best < 0 || at < best)))) {
        top = values[lane];
        best = at;
      }
    }
    return best;
  }
};

}  // namespace

/** The first k of the largest weight(k)·|alpha(k)| above `threshold`, or −1. */
int pickLargestAvx2(const double* alpha, const double* weight, int num_atoms, double threshold)
{
  LaneMaxima maxima{_mm256_set1_pd(threshold), _mm256_set1_pd(-1.0)};
  int k = 0;
  for (; k + 4 <= num_atoms; k += 4)
    maxima.offer(_mm256_loadu_pd(alpha + k), weight, k);
  double top;
  int best = maxima.first(threshold, top);
  for (; k < num_atoms; ++k) {
    const double value = (alpha[k] < 0 ? -alpha[k] : alpha[k]) * weight[k];
    if (value > top) {
      top = value;
      best = k;
    }
  }
  return best;
}

/** u(k) = (g(k) − Σ_i l(i)·basis(k, i)) · scale (i in order, by FMA), alpha(k) −= z·u(k) (FMA),
  * then the first k of the largest weight(k)·|alpha(k)| above `threshold`, or −1. Lanes keep
  * their own first maximum; equal maxima across lanes go to the smaller k. */
int projectUpdateAndPickAvx2(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                             double scale, double z, int num_atoms, const double* weight, double threshold, double* u,
                             double* alpha)
{
  LaneMaxima maxima{_mm256_set1_pd(threshold), _mm256_set1_pd(-1.0)};
  const __m256d scale_v = _mm256_set1_pd(scale), z_v = _mm256_set1_pd(z);
  int k = 0;
  // Four registers side by side, so that their chains of `size` FMAs overlap; offered to the
  // maxima in atom order, so each lane keeps its first maximum.
  for (; k + 16 <= num_atoms; k += 16) {
    __m256d v[4];
    for (int b = 0; b < 4; ++b)
      v[b] = _mm256_loadu_pd(g + k + 4 * b);
    for (int i = 0; i < size; ++i) {
      const __m256d li = _mm256_set1_pd(l[i]);
      const double* column = basis + i * stride + k;
      for (int b = 0; b < 4; ++b)
        v[b] = _mm256_fnmadd_pd(li, _mm256_loadu_pd(column + 4 * b), v[b]);
    }
    for (int b = 0; b < 4; ++b) {
      v[b] = _mm256_mul_pd(v[b], scale_v);
      _mm256_storeu_pd(u + k + 4 * b, v[b]);
      const __m256d a = _mm256_fnmadd_pd(z_v, v[b], _mm256_loadu_pd(alpha + k + 4 * b));
      _mm256_storeu_pd(alpha + k + 4 * b, a);
      maxima.offer(a, weight, k + 4 * b);
    }
  }
  for (; k + 4 <= num_atoms; k += 4) {
    __m256d v = _mm256_loadu_pd(g + k);
    for (int i = 0; i < size; ++i)
      v = _mm256_fnmadd_pd(_mm256_set1_pd(l[i]), _mm256_loadu_pd(basis + i * stride + k), v);
    v = _mm256_mul_pd(v, scale_v);
    _mm256_storeu_pd(u + k, v);
    const __m256d a = _mm256_fnmadd_pd(z_v, v, _mm256_loadu_pd(alpha + k));
    _mm256_storeu_pd(alpha + k, a);
    maxima.offer(a, weight, k);
  }
  double top;
  int best = maxima.first(threshold, top);
  for (; k < num_atoms; ++k) {
    double v = g[k];
    for (int i = 0; i < size; ++i)
      v = __builtin_fma(-l[i], basis[i * stride + k], v);
    v *= scale;
    u[k] = v;
    const double a = __builtin_fma(-z, v, alpha[k]);
    alpha[k] = a;
    const double value = (a < 0 ? -a : a) * weight[k];
    if (value > top) {
      top = value;
      best = k;
    }
  }
  return best;
}

/** out(k) = g(k) − Σ_i c(i)·columns[i][k] (i in order, by FMA; g null: from 0). */
void subtractCombinationAvx2(const double* g, const double* const* columns, const double* c, int count, int num_atoms,
                             double* out)
{
  int k = 0;
  for (; k + 4 <= num_atoms; k += 4) {
    __m256d v = g == nullptr ? _mm256_setzero_pd() : _mm256_loadu_pd(g + k);
    for (int i = 0; i < count; ++i)
      v = _mm256_fnmadd_pd(_mm256_set1_pd(c[i]), _mm256_loadu_pd(columns[i] + k), v);
    _mm256_storeu_pd(out + k, v);
  }
  for (; k < num_atoms; ++k) {
    double v = g == nullptr ? 0.0 : g[k];
    for (int i = 0; i < count; ++i)
      v = __builtin_fma(-c[i], columns[i][k], v);
    out[k] = v;
  }
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
