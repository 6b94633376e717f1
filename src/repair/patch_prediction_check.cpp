// checkPatchPrediction (see patch_prediction_check.h). The biharmonic grid fill is the discrete
// thin-plate interpolant (least-squares bi-Laplacian, as in Sorkine & Cohen-Or 2004, on the grid).
#include <pcl_patchdict/repair/patch_prediction_check.h>

#include <pcl_patchdict/core/error.h>

#include <Eigen/Dense>

#include <cmath>
#include <vector>

namespace pcl {
namespace patchdict {

namespace {

/** K with hidden = K · all-bins (visible entries used only): the biharmonic fill of the hidden bins. */
Eigen::MatrixXd biharmonicFillOperator(int n, const std::vector<int>& hidden)
{
  const int bins = n * n;
  std::vector<int> hidden_index(static_cast<std::size_t>(bins), -1);
  for (std::size_t i = 0; i < hidden.size(); ++i)
    hidden_index[static_cast<std::size_t>(hidden[i])] = static_cast<int>(i);
  // One 5-point Laplacian row per bin (fewer neighbours at the border).
  Eigen::MatrixXd laplacian = Eigen::MatrixXd::Zero(bins, bins);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int row = j * n + i;
      for (const auto& [di, dj] : {std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, -1}, std::pair{0, 1}}) {
        const int ii = i + di, jj = j + dj;
        if (ii < 0 || jj < 0 || ii >= n || jj >= n)
          continue;
        laplacian(row, jj * n + ii) -= 1.0;
        laplacian(row, row) += 1.0;
      }
    }
  Eigen::MatrixXd free_columns(bins, static_cast<Eigen::Index>(hidden.size()));
  for (std::size_t i = 0; i < hidden.size(); ++i)
    free_columns.col(static_cast<Eigen::Index>(i)) = laplacian.col(hidden[i]);
  Eigen::MatrixXd fixed = laplacian;
  for (int h : hidden)
    fixed.col(h).setZero();
  // min ‖A x + B y‖²: x = −(AᵀA)⁻¹ Aᵀ B y.
  return -(free_columns.transpose() * free_columns).ldlt().solve(free_columns.transpose() * fixed);
}

}  // namespace

PatchPredictionCheck checkPatchPrediction(const PatchSet& patches, double hidden_radius,
                                          const PatchDictionary::ConstPtr& dictionary,
                                          const PatchCorrectionParameters& parameters, std::size_t min_test_patches)
{
  PatchPredictionCheck check;
  const int n = patches.grid_size;
  if (n < 2 || !(patches.radius > 0.0) || !(hidden_radius > 0.0))
    return check;
  if (dictionary && dictionary->gridSize() != n)
    throw Error("the dictionary's grid does not match the patches'");
  std::vector<Eigen::Index> full;
  for (Eigen::Index k = 0; k < patches.heights.cols(); ++k)
    if (patches.observed.col(k).all())
      full.push_back(k);
  std::vector<Eigen::Index> train, test;
  for (std::size_t i = 0; i < full.size(); ++i)
    (dictionary || i % 2 == 1 ? test : train).push_back(full[i]);
  if (test.size() < min_test_patches || (!dictionary && train.size() < min_test_patches))
    return check;

  const double side = patches.radius * std::sqrt(2.0);
  const double radius_bins = hidden_radius / side * n;
  std::vector<int> hidden;
  for (int b = 0; b < n * n; ++b)
    if (std::hypot(b % n - 0.5 * (n - 1), b / n - 0.5 * (n - 1)) < radius_bins)
      hidden.push_back(b);
  if (hidden.empty() || static_cast<int>(hidden.size()) == n * n)
    return check;
  check.hidden_bins = hidden.size();
  check.test_patches = test.size();

  const Eigen::Index bins = static_cast<Eigen::Index>(n) * n;
  PatchDictionary::ConstPtr atoms = dictionary;
  if (!atoms) {
    Eigen::MatrixXd heights(bins, static_cast<Eigen::Index>(train.size()));
    for (std::size_t i = 0; i < train.size(); ++i)
      heights.col(static_cast<Eigen::Index>(i)) = patches.heights.col(train[i]);
    atoms = PatchCorrection::learnSelfSimilar(heights, ObservationMask::Constant(bins, heights.cols(), true),
                                              parameters);
  }
  Eigen::MatrixXd heights(bins, static_cast<Eigen::Index>(test.size()));
  for (std::size_t i = 0; i < test.size(); ++i)
    heights.col(static_cast<Eigen::Index>(i)) = patches.heights.col(test[i]);
  ObservationMask mask = ObservationMask::Constant(bins, heights.cols(), true);
  for (int h : hidden)
    mask.row(h).setConstant(false);
  SparseCodingParameters coding;
  coding.max_atoms = std::min<int>(parameters.sparsity, static_cast<int>(atoms->atoms().cols()));
  const Eigen::MatrixXd predicted = atoms->decode(atoms->encodeMasked(heights, mask, coding));
  const Eigen::MatrixXd fill = biharmonicFillOperator(n, hidden) * heights;
  double dictionary_sum = 0.0, biharmonic_sum = 0.0;
  for (Eigen::Index c = 0; c < heights.cols(); ++c)
    for (std::size_t i = 0; i < hidden.size(); ++i) {
      const double truth = heights(hidden[i], c);
      dictionary_sum += std::pow(predicted(hidden[i], c) - truth, 2);
      biharmonic_sum += std::pow(fill(static_cast<Eigen::Index>(i), c) - truth, 2);
    }
  const double count = static_cast<double>(heights.cols()) * static_cast<double>(hidden.size());
  check.dictionary_rms = std::sqrt(dictionary_sum / count);
  check.biharmonic_rms = std::sqrt(biharmonic_sum / count);
  check.gain = check.dictionary_rms > 0.0 ? check.biharmonic_rms / check.dictionary_rms : 0.0;
  return check;
}

}  // namespace patchdict
}  // namespace pcl
