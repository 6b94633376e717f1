// The AVX-512 kernels of computeCorrelations, pickLargest, projectUpdateAndPick and
// subtractCombination, compiled with -mavx512f: the AVX2 kernels' sums in the same order, so they
// give the same bits, twice as wide.
// As in correlations_avx2.cpp nothing here is a header's template or inline function (no Eigen, no
// std::); the templates below live in an anonymous namespace, so no other file can link to them.
// GCC 12's AVX-512 intrinsics pass _mm512_undefined_pd() (deliberately uninitialised) to the
// builtins, which -Wuninitialized then reports from inside the header (GCC bug 105593, fixed in 13).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <cstddef>

namespace pcl {
namespace patchdict {
namespace detail {

/** One dot product in the AVX2 kernel's order (correlations_avx2.cpp: a function of its own, not
  * inline, so the same code serves both kernels; every CPU that runs these has AVX2 + FMA). */
double dotAvx2(const double* a, const double* b, std::ptrdiff_t n);

namespace {

/** Two four-row slices in one register: a's rows i … i+3 below, b's above. */
inline __m512d pairAt(const double* a, const double* b, std::ptrdiff_t i)
{
  return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(a + i)), _mm256_loadu_pd(b + i), 1);
}

/** The lane sums of two pair accumulators A = (atoms a, c) and B = (b, d), four lanes each:
  * [a, b, c, d] in the low halves' order of _mm512_shuffle_f64x2 below. Per atom the sum is
  * (l0 + l1) + (l2 + l3), as the AVX2 kernel's laneSum: IEEE addition is commutative, so the bits agree. */
inline __m512d pairSums(__m512d A, __m512d B)
{
  // Position 2j: A's lanes 2j + (2j+1); position 2j+1: B's.
  return _mm512_add_pd(_mm512_shuffle_pd(A, B, 0x00), _mm512_shuffle_pd(A, B, 0xFF));
}

/** The eight-atom panels the kernel reads: per four rows, the pairs of atoms (0, 2), (1, 3),
  * (4, 6), (5, 7) of each block of eight, four rows of each, so that one aligned load fetches a
  * pair and the lane sums land in atom order. */
void packPanels(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t body, std::ptrdiff_t blocks,
                double* panels)
{
  constexpr int order[8] = {0, 2, 1, 3, 4, 6, 5, 7};
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    const double* d = atoms + b * 8 * atom_stride;
    for (std::ptrdiff_t i = 0; i < body; i += 4)
      for (int a = 0; a < 8; ++a) {
        _mm256_store_pd(panels, _mm256_loadu_pd(d + order[a] * atom_stride + i));
        panels += 4;
      }
  }
}

/** Rows 0 … body of atoms k … k+2P−1 against Q signals, into out, then the leftover rows. The
  * pair accumulators hold atoms (0, 2), (1, 3), (4, 6), (5, 7) of the block, so the lane sums land
  * in atom order without a permutation. Eight atoms come from their packed panel, four (the
  * dictionary's last block, if any) straight from the columns. */
template <int P, int Q>
void block(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, const double* panel,
           const double* const* x, double* out, std::ptrdiff_t out_stride)
{
  static_assert(P == 2 || P == 4, "blocks of 4 or 8 atoms");
  const std::ptrdiff_t body = n & ~std::ptrdiff_t{3};
  __m512d acc[P][Q];
  for (int a = 0; a < P; ++a)
    for (int s = 0; s < Q; ++s)
      acc[a][s] = _mm512_setzero_pd();
  for (std::ptrdiff_t i = 0; i < body; i += 4) {
    __m512d xv[Q];
    for (int s = 0; s < Q; ++s)
      xv[s] = _mm512_broadcast_f64x4(_mm256_loadu_pd(x[s] + i));
    for (int a = 0; a < P; ++a) {
      const __m512d dv = P == 4 ? _mm512_load_pd(panel + 8 * i + 8 * a)
                                : pairAt(atoms + a * atom_stride, atoms + (a + 2) * atom_stride, i);
      for (int s = 0; s < Q; ++s)
        acc[a][s] = _mm512_fmadd_pd(dv, xv[s], acc[a][s]);
    }
  }
  for (int s = 0; s < Q; ++s) {
    double* o = out + s * out_stride;
    if (P == 4) {
      const __m512d ab = pairSums(acc[0][s], acc[1][s]), cd = pairSums(acc[2][s], acc[3][s]);
      // [ab.L0, ab.L2, cd.L0, cd.L2] + [ab.L1, ab.L3, cd.L1, cd.L3] = atoms 0 … 7.
      _mm512_storeu_pd(o, _mm512_add_pd(_mm512_shuffle_f64x2(ab, cd, 0x88), _mm512_shuffle_f64x2(ab, cd, 0xDD)));
    } else {
      const __m512d ab = pairSums(acc[0][s], acc[1][s]);
      _mm256_storeu_pd(o, _mm256_add_pd(_mm512_castpd512_pd256(_mm512_shuffle_f64x2(ab, ab, 0x88)),
                                        _mm512_castpd512_pd256(_mm512_shuffle_f64x2(ab, ab, 0xDD))));
    }
    for (int a = 0; a < 2 * P; ++a) {
      const double* d = atoms + a * atom_stride;
      double total = o[a];
      for (std::ptrdiff_t i = body; i < n; ++i)
        total = __builtin_fma(d[i], x[s][i], total);
      o[a] = total;
    }
  }
}

/** All atoms against Q signals: blocks of 8, one of 4, then single dot products. */
template <int Q>
void signalBlock(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, std::ptrdiff_t num_atoms,
                 const double* panels, const double* const* x, double* out, std::ptrdiff_t out_stride)
{
  const std::ptrdiff_t body = n & ~std::ptrdiff_t{3};
  std::ptrdiff_t k = 0;
  for (; k + 8 <= num_atoms; k += 8)
    block<4, Q>(atoms + k * atom_stride, atom_stride, n, panels + k * body, x, out + k, out_stride);
  for (; k + 4 <= num_atoms; k += 4)
    block<2, Q>(atoms + k * atom_stride, atom_stride, n, nullptr, x, out + k, out_stride);
  for (; k < num_atoms; ++k)
    for (int s = 0; s < Q; ++s)
      out[s * out_stride + k] = dotAvx2(atoms + k * atom_stride, x[s], n);
}

}  // namespace

std::ptrdiff_t correlationsAvx512PanelSize(std::ptrdiff_t n, std::ptrdiff_t num_atoms)
{
  return (num_atoms / 8) * 8 * (n & ~std::ptrdiff_t{3});
}

/** out(k, p) = Σ_i atoms(i, k) · signals(i, p), all column-major, each entry summed as
  * correlationsAvx2 sums it. `panels`: correlationsAvx512PanelSize(n, num_atoms) doubles, 64-byte
  * aligned, the caller's scratch. */
void correlationsAvx512(const double* atoms, std::ptrdiff_t atom_stride, std::ptrdiff_t n, std::ptrdiff_t num_atoms,
                        const double* signals, std::ptrdiff_t signal_stride, std::ptrdiff_t num_signals, double* out,
                        std::ptrdiff_t out_stride, double* panels)
{
  // 4 pairs × 6 signals: 24 accumulators, 6 signal registers and one pair of atoms in the 32.
  // Packing costs n·K copies per call, against n·K·P multiply-adds.
  constexpr int kSignals = 6;
  packPanels(atoms, atom_stride, n & ~std::ptrdiff_t{3}, num_atoms / 8, panels);
  const double* x[kSignals];
  for (std::ptrdiff_t p = 0; p < num_signals; p += kSignals) {
    const std::ptrdiff_t count = num_signals - p < kSignals ? num_signals - p : kSignals;
    for (std::ptrdiff_t s = 0; s < count; ++s)
      x[s] = signals + (p + s) * signal_stride;
    double* o = out + p * out_stride;
    switch (count) {
      case 6: signalBlock<6>(atoms, atom_stride, n, num_atoms, panels, x, o, out_stride); break;
      case 5: signalBlock<5>(atoms, atom_stride, n, num_atoms, panels, x, o, out_stride); break;
      case 4: signalBlock<4>(atoms, atom_stride, n, num_atoms, panels, x, o, out_stride); break;
      case 3: signalBlock<3>(atoms, atom_stride, n, num_atoms, panels, x, o, out_stride); break;
      case 2: signalBlock<2>(atoms, atom_stride, n, num_atoms, panels, x, o, out_stride); break;
      default: signalBlock<1>(atoms, atom_stride, n, num_atoms, panels, x, o, out_stride); break;
    }
  }
}

namespace {

/** Running first maxima of weight·|α| per lane, and their atom indices. */
struct LaneMaxima {
  __m512d value, index;
  /** Takes the lanes of `a` (atoms k … k+7 where `live`) that beat the maxima so far. */
  inline void offer(__m512d a, const double* weight, int k, __mmask8 live)
  {
    const __m512d v = _mm512_mul_pd(_mm512_abs_pd(a), _mm512_maskz_loadu_pd(live, weight + k));
    const __mmask8 better = _mm512_mask_cmp_pd_mask(live, v, value, _CMP_GT_OQ);
    value = _mm512_mask_blend_pd(better, value, v);
    index = _mm512_mask_blend_pd(better, index,
                                 _mm512_add_pd(_mm512_set1_pd(static_cast<double>(k)),
                                               _mm512_setr_pd(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0)));
  }
};

/** The first largest of four registers' lane maxima, or −1 when none rose above the threshold (the
  * value the lanes start from): the largest value, then the smallest atom holding it. */
int firstLargest(const LaneMaxima* maxima, double threshold)
{
  const double best = _mm512_reduce_max_pd(_mm512_max_pd(_mm512_max_pd(maxima[0].value, maxima[1].value),
                                                         _mm512_max_pd(maxima[2].value, maxima[3].value)));
  if (!(best > threshold))
    return -1;
  const __m512d target = _mm512_set1_pd(best);
  __m512d smallest = _mm512_set1_pd(2147483647.0);
  for (int b = 0; b < 4; ++b)  // a lane at the maximum was raised above the threshold: its index is an atom
    smallest = _mm512_mask_min_pd(smallest, _mm512_cmp_pd_mask(maxima[b].value, target, _CMP_EQ_OQ), smallest,
                                  maxima[b].index);
  return static_cast<int>(_mm512_reduce_min_pd(smallest));
}

void startMaxima(LaneMaxima* maxima, double threshold)
{
  for (int b = 0; b < 4; ++b) {
    maxima[b].value = _mm512_set1_pd(threshold);
    maxima[b].index = _mm512_set1_pd(-1.0);
  }
}

/** The projected step for atoms k … k+8B−1 (B registers side by side, so that their chains of
  * `size` FMAs overlap), `live` lanes of the last register only. */
template <int B>
inline void projectBlocks(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                          __m512d scale, __m512d z, int k, const double* weight, double* u, double* alpha,
                          LaneMaxima* maxima, __mmask8 live)
{
  __m512d v[B];
  for (int b = 0; b < B; ++b)
    v[b] = _mm512_maskz_loadu_pd(b == B - 1 ? live : __mmask8(0xFF), g + k + 8 * b);
  for (int i = 0; i < size; ++i) {
    const __m512d li = _mm512_set1_pd(l[i]);
    const double* column = basis + i * stride + k;
    for (int b = 0; b < B; ++b)
      v[b] = _mm512_fnmadd_pd(li, _mm512_maskz_loadu_pd(b == B - 1 ? live : __mmask8(0xFF), column + 8 * b), v[b]);
  }
  for (int b = 0; b < B; ++b) {
    const __mmask8 m = b == B - 1 ? live : __mmask8(0xFF);
    v[b] = _mm512_mul_pd(v[b], scale);
    _mm512_mask_storeu_pd(u + k + 8 * b, m, v[b]);
    const __m512d a = _mm512_fnmadd_pd(z, v[b], _mm512_maskz_loadu_pd(m, alpha + k + 8 * b));
    _mm512_mask_storeu_pd(alpha + k + 8 * b, m, a);
    maxima[b].offer(a, weight, k + 8 * b, m);
  }
}

}  // namespace

/** pickLargest eight lanes wide. */
int pickLargestAvx512(const double* alpha, const double* weight, int num_atoms, double threshold)
{
  LaneMaxima maxima[4];
  startMaxima(maxima, threshold);
  int k = 0;
  for (; k + 32 <= num_atoms; k += 32)
    for (int b = 0; b < 4; ++b)
      maxima[b].offer(_mm512_loadu_pd(alpha + k + 8 * b), weight, k + 8 * b, 0xFF);
  for (; k < num_atoms; k += 8) {
    const __mmask8 live = num_atoms - k >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (num_atoms - k)) - 1u);
    maxima[1].offer(_mm512_maskz_loadu_pd(live, alpha + k), weight, k, live);
  }
  return firstLargest(maxima, threshold);
}

/** projectUpdateAndPickAvx2 eight lanes wide: the same FMA chain per atom, the same first maximum.
  * Four registers of atoms go side by side: one register's chain of `size` FMAs alone would wait
  * on the FMA latency at every step. */
int projectUpdateAndPickAvx512(const double* g, const double* basis, std::ptrdiff_t stride, const double* l, int size,
                               double scale, double z, int num_atoms, const double* weight, double threshold,
                               double* u, double* alpha)
{
  LaneMaxima maxima[4];
  startMaxima(maxima, threshold);
  const __m512d scale_v = _mm512_set1_pd(scale), z_v = _mm512_set1_pd(z);
  int k = 0;
  for (; k + 32 <= num_atoms; k += 32)
    projectBlocks<4>(g, basis, stride, l, size, scale_v, z_v, k, weight, u, alpha, maxima, 0xFF);
  for (; k < num_atoms; k += 8) {
    const __mmask8 live = num_atoms - k >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (num_atoms - k)) - 1u);
    projectBlocks<1>(g, basis, stride, l, size, scale_v, z_v, k, weight, u, alpha, maxima + 1, live);
  }
  return firstLargest(maxima, threshold);
}

/** subtractCombination eight lanes wide, four registers side by side; the same FMA chain per
  * entry as the AVX2 kernel. */
void subtractCombinationAvx512(const double* g, const double* const* columns, const double* c, int count,
                               int num_atoms, double* out)
{
  for (int k = 0; k < num_atoms; k += 32) {
    __mmask8 live[4];
    for (int b = 0; b < 4; ++b) {
      const int left = num_atoms - k - 8 * b;
      live[b] = left >= 8 ? __mmask8(0xFF) : left <= 0 ? __mmask8(0) : static_cast<__mmask8>((1u << left) - 1u);
    }
    __m512d v[4];
    for (int b = 0; b < 4; ++b)
      v[b] = g == nullptr ? _mm512_setzero_pd() : _mm512_maskz_loadu_pd(live[b], g + k + 8 * b);
    for (int i = 0; i < count; ++i) {
      const __m512d ci = _mm512_set1_pd(c[i]);
      for (int b = 0; b < 4; ++b)
        v[b] = _mm512_fnmadd_pd(ci, _mm512_maskz_loadu_pd(live[b], columns[i] + k + 8 * b), v[b]);
    }
    for (int b = 0; b < 4; ++b)
      _mm512_mask_storeu_pd(out + k + 8 * b, live[b], v[b]);
  }
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
