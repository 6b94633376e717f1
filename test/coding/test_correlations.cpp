// computeCorrelations (Dᵀx for Batch-OMP): equal to Eigen's product to rounding for every shape
// (rows, atoms and signals that are not multiples of the kernel's blocks), and each entry the same
// bits whatever the batch it is computed in.
#include "coding/correlations.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

using pcl::patchdict::detail::computeCorrelations;

using test_support::gaussianMatrix;

TEST(Correlations, EqualEigensProductForEveryShape)
{
  RecordProperty("avx2", pcl::patchdict::detail::correlationsUseAvx2() ? "yes" : "no");
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
  if (!pcl::patchdict::detail::correlationsUseAvx2())
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

// The fused Batch-OMP step: the same α bits and the same pick from every kernel, including ties
// (the first maximum wins) and excluded atoms, for atom counts that leave every tail length.
TEST(Correlations, UpdateAndPickAgreesAcrossKernels)
{
  using pcl::patchdict::detail::SimdKernels;
  using pcl::patchdict::detail::updateCorrelationsAndPick;
  std::vector<SimdKernels> kernels{SimdKernels::Portable};
  if (pcl::patchdict::detail::bestSimdKernels() != SimdKernels::Portable)
    kernels.push_back(SimdKernels::Avx2);
  if (pcl::patchdict::detail::bestSimdKernels() == SimdKernels::Avx512)
    kernels.push_back(SimdKernels::Avx512);
  for (const int num_atoms : {1, 3, 4, 7, 8, 9, 15, 16, 17, 100, 501})
    for (const int size : {0, 1, 3}) {
      const Eigen::MatrixXd g = gaussianMatrix(num_atoms, 3, 7 + num_atoms);
      Eigen::VectorXd alpha0 = gaussianMatrix(num_atoms, 1, 8 + num_atoms).col(0);
      // A tie between the last atom and an earlier one, which must lose to the earlier one.
      if (size == 0 && num_atoms > 2)
        alpha0[num_atoms - 1] = -alpha0.cwiseAbs().maxCoeff();
      Eigen::VectorXd weight = Eigen::VectorXd::Ones(num_atoms);
      if (num_atoms > 5)
        weight[num_atoms / 2] = 0.0;
      const double gamma[3] = {0.5, -1.25, 2.0};
      const double* columns[3] = {g.col(0).data(), g.col(1).data(), g.col(2).data()};
      Eigen::VectorXd reference_alpha(num_atoms);
      int reference = -2;
      for (const SimdKernels which : kernels) {
        Eigen::VectorXd alpha(num_atoms);
        const int best = updateCorrelationsAndPick(alpha0.data(), columns, gamma, size, num_atoms, weight.data(), 1e-12,
                                                   alpha.data(), which);
        if (which == SimdKernels::Portable) {
          // No FMA here: the index, and α to rounding.
          reference = best;
          reference_alpha = alpha;
          Eigen::Index expected = 0;
          (alpha.cwiseAbs().cwiseProduct(weight)).maxCoeff(&expected);
          EXPECT_EQ(best, static_cast<int>(expected)) << num_atoms << " " << size;
          continue;
        }
        EXPECT_EQ(best, reference) << num_atoms << " " << size << " kernels " << static_cast<int>(which);
        EXPECT_LE((alpha - reference_alpha).cwiseAbs().maxCoeff(), 1e-14) << num_atoms << " " << size;
        if (which == SimdKernels::Avx512) {
          Eigen::VectorXd narrow(num_atoms);
          updateCorrelationsAndPick(alpha0.data(), columns, gamma, size, num_atoms, weight.data(), 1e-12,
                                    narrow.data(), SimdKernels::Avx2);
          EXPECT_EQ(std::memcmp(alpha.data(), narrow.data(), sizeof(double) * static_cast<std::size_t>(num_atoms)), 0)
              << num_atoms << " " << size;
        }
      }
    }
}
