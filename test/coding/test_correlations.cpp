// computeCorrelations (Dᵀx for Batch-OMP): equal to Eigen's product to rounding for every shape
// (rows, atoms and signals that are not multiples of the kernel's blocks), and each entry the same
// bits whatever the batch it is computed in.
#include "coding/correlations.h"

#include <pcl_patchdict/coding/sparse_coding.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

using pcl::patchdict::detail::computeCorrelations;

using test_support::gaussianMatrix;

namespace {

/** The kernels this CPU can run, narrowest first. */
std::vector<pcl::patchdict::detail::SimdKernels> availableKernels()
{
  using pcl::patchdict::detail::SimdKernels;
  std::vector<SimdKernels> kernels{SimdKernels::Portable};
  if (pcl::patchdict::detail::bestSimdKernels() != SimdKernels::Portable)
    kernels.push_back(SimdKernels::Avx2);
  if (pcl::patchdict::detail::bestSimdKernels() == SimdKernels::Avx512)
    kernels.push_back(SimdKernels::Avx512);
  return kernels;
}

}  // namespace

TEST(Correlations, EqualEigensProductForEveryShape)
{
  RecordProperty("kernels", pcl::patchdict::sparseCodingKernels());
  for (const Eigen::Index n : {1, 3, 4, 7, 64, 257})
    for (const Eigen::Index atoms : {1, 3, 4, 5, 9, 100})
      for (const Eigen::Index signals : {1, 2, 3, 4, 7, 31}) {
        const Eigen::MatrixXd d = gaussianMatrix(n, atoms, 1 + n), x = gaussianMatrix(n, signals, 2 + atoms);
        Eigen::MatrixXd c;
        computeCorrelations(d, x, c);
        ASSERT_EQ(c.rows(), atoms);
        ASSERT_EQ(c.cols(), signals);
        const Eigen::MatrixXd reference = d.transpose() * x;
        // Each entry is a sum of n products of Gaussians: rounding grows like √n·ε·(scale).
        EXPECT_LE((c - reference).cwiseAbs().maxCoeff(), 1e-13 * static_cast<double>(n)) << n << " " << atoms << " "
                                                                                           << signals;
      }
}

TEST(Correlations, EachEntryHasTheSameBitsInAnyBatch)
{
  if (pcl::patchdict::detail::activeSimdKernels() == pcl::patchdict::detail::SimdKernels::Portable)
    GTEST_SKIP() << "Eigen's product (no AVX2 here) promises the same bits for the same batch only";
  const Eigen::MatrixXd d = gaussianMatrix(256, 101, 5), x = gaussianMatrix(256, 40, 6);
  Eigen::MatrixXd all;
  computeCorrelations(d, x, all);
  for (Eigen::Index start : {0, 1, 5, 38}) {
    for (Eigen::Index size : {1, 2, 3}) {
      if (start + size > x.cols())
        continue;
      Eigen::MatrixXd part;
      computeCorrelations(d, x.middleCols(start, size), part);  // a strided view, as batchOMP passes
      for (Eigen::Index j = 0; j < size; ++j)
        for (Eigen::Index k = 0; k < d.cols(); ++k)
          ASSERT_EQ(part(k, j), all(k, start + j)) << start << " " << size << " " << k;
    }
  }
}

// Every kernel this CPU can run gives the AVX2 kernel's bits: for shapes that hit each block size
// and tail of the AVX-512 kernel (8- and 4-atom blocks, single atoms; 1 … 6 signals; leftover rows).
TEST(Correlations, WiderKernelsGiveTheAvx2KernelsBits)
{
  using pcl::patchdict::detail::SimdKernels;
  if (pcl::patchdict::detail::bestSimdKernels() != SimdKernels::Avx512)
    GTEST_SKIP() << "this CPU has no AVX-512: nothing wider than AVX2 to compare";
  int compared = 0;
  for (const Eigen::Index n : {1, 4, 6, 64, 256, 259})
    for (const Eigen::Index atoms : {1, 2, 3, 4, 7, 8, 12, 13, 100, 500})
      for (const Eigen::Index signals : {1, 2, 3, 5, 6, 7, 13}) {
        const Eigen::MatrixXd d = gaussianMatrix(n, atoms, 3 + n), x = gaussianMatrix(n + 2, signals, 4 + atoms);
        Eigen::MatrixXd narrow, wide;
        computeCorrelations(d, x.topRows(n), narrow, SimdKernels::Avx2);  // a strided view
        computeCorrelations(d, x.topRows(n), wide, SimdKernels::Avx512);
        ASSERT_EQ(wide.rows(), atoms);
        ASSERT_EQ(wide.cols(), signals);
        for (Eigen::Index p = 0; p < signals; ++p)
          for (Eigen::Index k = 0; k < atoms; ++k)
            ASSERT_EQ(std::memcmp(&wide(k, p), &narrow(k, p), sizeof(double)), 0)
                << n << " " << atoms << " " << signals << " entry " << k << "," << p;
        ++compared;
      }
  EXPECT_EQ(compared, 6 * 10 * 7);
}

// The fused Batch-OMP step and the first pick: the same u and α bits and the same pick from every
// SIMD kernel, the plain loops' to rounding; ties go to the first maximum, excluded atoms are never
// picked; atom counts leave every tail length.
TEST(Correlations, ProjectedStepAgreesAcrossKernels)
{
  using pcl::patchdict::detail::pickLargest;
  using pcl::patchdict::detail::projectUpdateAndPick;
  using pcl::patchdict::detail::SimdKernels;
  const std::vector<SimdKernels> kernels = availableKernels();
  int checked = 0;
  for (const int num_atoms : {1, 3, 4, 7, 8, 9, 15, 16, 17, 31, 33, 100, 501})
    for (const int size : {0, 1, 3}) {
      const Eigen::MatrixXd basis = gaussianMatrix(num_atoms, 3, 7 + num_atoms);
      const Eigen::VectorXd g = gaussianMatrix(num_atoms, 1, 9 + num_atoms).col(0);
      Eigen::VectorXd alpha0 = gaussianMatrix(num_atoms, 1, 8 + num_atoms).col(0);
      // A tie between the last atom and an earlier one, which must lose to the earlier one.
      if (num_atoms > 2)
        alpha0[num_atoms - 1] = -alpha0.cwiseAbs().maxCoeff();
      Eigen::VectorXd weight = Eigen::VectorXd::Ones(num_atoms);
      if (num_atoms > 5)
        weight[num_atoms / 2] = 0.0;
      const double l[3] = {0.5, -1.25, 2.0};
      const double scale = 0.75, z = size == 0 ? 0.0 : -1.5;  // z = 0: α unchanged, the tie stays
      Eigen::VectorXd reference_alpha, reference_u, simd_alpha, simd_u;
      for (const SimdKernels which : kernels) {
        // The first pick, from α0 itself.
        Eigen::Index expected = 0;
        alpha0.cwiseAbs().cwiseProduct(weight).maxCoeff(&expected);  // Eigen's maxCoeff keeps the first
        ASSERT_EQ(pickLargest(alpha0.data(), weight.data(), num_atoms, 1e-12, which), static_cast<int>(expected))
            << num_atoms << " kernels " << static_cast<int>(which);
        Eigen::VectorXd alpha = alpha0, u(num_atoms);
        const int best = projectUpdateAndPick(g.data(), basis.data(), basis.outerStride(), l, size, scale, z,
                                              num_atoms, weight.data(), 1e-12, u.data(), alpha.data(), which);
        // Against the formula, independently of any kernel.
        Eigen::VectorXd expected_u = g;
        for (int i = 0; i < size; ++i)
          expected_u -= l[i] * basis.col(i);
        expected_u *= scale;
        const Eigen::VectorXd expected_alpha = alpha0 - z * expected_u;
        EXPECT_LE((u - expected_u).cwiseAbs().maxCoeff(), 1e-13) << num_atoms << " " << size;
        EXPECT_LE((alpha - expected_alpha).cwiseAbs().maxCoeff(), 1e-13) << num_atoms << " " << size;
        expected_alpha.cwiseAbs().cwiseProduct(weight).maxCoeff(&expected);
        EXPECT_EQ(best, static_cast<int>(expected)) << num_atoms << " " << size << " kernels " << static_cast<int>(which);
        if (num_atoms > 5) {
          EXPECT_NE(best, num_atoms / 2);
        }
        if (which == SimdKernels::Avx2) {
          simd_alpha = alpha;
          simd_u = u;
        } else if (which == SimdKernels::Avx512) {
          EXPECT_EQ(std::memcmp(alpha.data(), simd_alpha.data(), sizeof(double) * static_cast<std::size_t>(num_atoms)), 0);
          EXPECT_EQ(std::memcmp(u.data(), simd_u.data(), sizeof(double) * static_cast<std::size_t>(num_atoms)), 0);
        }
        ++checked;
      }
    }
  EXPECT_EQ(checked, 13 * 3 * static_cast<int>(kernels.size()));
}

// A masked Gram column from a few rows: the formula to rounding from every kernel, the same bits from
// the AVX2 and AVX-512 kernels, for lengths that leave every tail, with and without a start column.
TEST(Correlations, SubtractCombinationAgreesAcrossKernels)
{
  using pcl::patchdict::detail::SimdKernels;
  using pcl::patchdict::detail::subtractCombination;
  const std::vector<SimdKernels> kernels = availableKernels();
  for (const int num_atoms : {1, 5, 8, 13, 31, 32, 33, 100})
    for (const int count : {0, 1, 7})
      for (const bool start : {false, true}) {
        const Eigen::MatrixXd rows = gaussianMatrix(num_atoms, 7, 11 + num_atoms);
        const Eigen::VectorXd g = gaussianMatrix(num_atoms, 1, 12 + num_atoms).col(0);
        const Eigen::VectorXd c = gaussianMatrix(7, 1, 13).col(0);
        std::vector<const double*> columns;
        for (int i = 0; i < 7; ++i)
          columns.push_back(rows.col(i).data());
        const Eigen::VectorXd expected =
            (start ? g : Eigen::VectorXd::Zero(num_atoms)) - rows.leftCols(count) * c.head(count);
        Eigen::VectorXd avx2;
        for (const SimdKernels which : kernels) {
          Eigen::VectorXd out = Eigen::VectorXd::Constant(num_atoms, 99.0);
          subtractCombination(start ? g.data() : nullptr, columns.data(), c.data(), count, num_atoms, out.data(), which);
          EXPECT_LE((out - expected).cwiseAbs().maxCoeff(), 1e-13) << num_atoms << " " << count << " " << start;
          if (which == SimdKernels::Avx2)
            avx2 = out;
          if (which == SimdKernels::Avx512) {
            EXPECT_EQ(std::memcmp(out.data(), avx2.data(), sizeof(double) * static_cast<std::size_t>(num_atoms)), 0);
          }
        }
      }
}

// Ties decide the support: the first (smallest) atom at the maximum must win, whether the tied
// atoms share a SIMD lane (k and k + 8, k and k + 4) or not, sit in one register block or two, or
// one sits in a scalar tail; an excluded atom loses even when it holds the largest value.
TEST(Correlations, TheFirstMaximumWinsTiesInEveryKernel)
{
  using pcl::patchdict::detail::pickLargest;
  using pcl::patchdict::detail::projectUpdateAndPick;
  int cases = 0;
  for (const int num_atoms : {9, 13, 17, 40, 67, 100})
    for (const int first : {0, 1, 3, 5})
      for (const int gap : {1, 3, 4, 8, 16, 32, 33}) {
        const int second = first + gap;
        if (second >= num_atoms)
          continue;
        Eigen::VectorXd alpha0 = 0.5 * gaussianMatrix(num_atoms, 1, 20 + num_atoms).col(0).cwiseMin(1.0).cwiseMax(-1.0);
        alpha0[first] = 3.0;
        alpha0[second] = -3.0;  // the same weighted |α|
        const int excluded = num_atoms - 1;
        Eigen::VectorXd weight = Eigen::VectorXd::Ones(num_atoms);
        if (excluded != second && excluded != first) {
          alpha0[excluded] = 7.0;  // the largest, but excluded
          weight[excluded] = 0.0;
        }
        const Eigen::VectorXd zeros = Eigen::VectorXd::Zero(num_atoms);
        for (const auto which : availableKernels()) {
          EXPECT_EQ(pickLargest(alpha0.data(), weight.data(), num_atoms, 1e-12, which), first)
              << num_atoms << " " << first << " " << second << " kernels " << static_cast<int>(which);
          // The fused step with z = 0 leaves α as it is and must pick the same atom.
          Eigen::VectorXd alpha = alpha0, u(num_atoms);
          EXPECT_EQ(projectUpdateAndPick(zeros.data(), zeros.data(), num_atoms, nullptr, 0, 1.0, 0.0, num_atoms,
                                         weight.data(), 1e-12, u.data(), alpha.data(), which),
                    first)
              << num_atoms << " " << first << " " << second << " kernels " << static_cast<int>(which);
          ++cases;
        }
      }
  EXPECT_GT(cases, 100);
}
