// computeCorrelations (Dᵀx for Batch-OMP): equal to Eigen's product to rounding for every shape
// (rows, atoms and signals that are not multiples of the kernel's blocks), and each entry the same
// bits whatever the batch it is computed in.
#include "coding/correlations.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

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
