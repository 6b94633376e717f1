// Patch dictionaries over pcl::Histogram clouds: learned from histograms it is the dictionary
// learned from the equivalent matrix and mask (same fingerprint); coding histograms with NaN bins
// reproduces the observed bins and fills the hidden ones; conversions and size errors.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/pcl/patch_histograms.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace pcl::patchdict;

namespace {

using Histogram64 = pcl::Histogram<64>;

/** 400 patches of 8 × 8 bins, each a combination of three of 16 random unit atoms (coefficients
  * ±[0.5, 1.5]), rounded to float (what a histogram holds); `hidden` of the bins unobserved at
  * random (height 0 there, as histogramsToPatches makes a NaN bin). The same patches for any
  * `hidden`: the mask has a generator of its own. */
void sparsePatches(double hidden, Eigen::MatrixXd& patches, ObservationMask& observed, Eigen::MatrixXd* atoms = nullptr)
{
  std::mt19937_64 random(5), mask_random(6);
  std::normal_distribution<double> gaussian;
  std::uniform_real_distribution<double> magnitude(0.5, 1.5);
  std::uniform_int_distribution<int> pick(0, 15);
  std::bernoulli_distribution hide(hidden);
  Eigen::MatrixXd basis(64, 16);
  for (Eigen::Index i = 0; i < basis.size(); ++i)
    basis.data()[i] = gaussian(random);
  basis.colwise().normalize();
  patches = Eigen::MatrixXd::Zero(64, 400);
  observed.resize(64, 400);
  for (int p = 0; p < 400; ++p) {
    int chosen[3] = {pick(random), 0, 0};
    do chosen[1] = pick(random); while (chosen[1] == chosen[0]);
    do chosen[2] = pick(random); while (chosen[2] == chosen[0] || chosen[2] == chosen[1]);
    for (const int k : chosen)
      patches.col(p) += (random() % 2 ? 1.0 : -1.0) * magnitude(random) * basis.col(k);
    for (int b = 0; b < 64; ++b) {
      patches(b, p) = static_cast<double>(static_cast<float>(patches(b, p)));
      observed(b, p) = !hide(mask_random);
      if (!observed(b, p))
        patches(b, p) = 0.0;
    }
  }
  if (atoms)
    *atoms = basis;
}

pcl::PointCloud<Histogram64> asHistograms(const Eigen::MatrixXd& patches, const ObservationMask& observed)
{
  pcl::PointCloud<Histogram64> histograms;
  patchesToHistograms(patches, observed, histograms);
  return histograms;
}

}  // namespace

TEST(PatchHistograms, ConversionsPutNaNExactlyInTheUnobservedBins)
{
  Eigen::MatrixXd patches;
  ObservationMask observed;
  sparsePatches(0.25, patches, observed);
  const auto histograms = asHistograms(patches, observed);
  ASSERT_EQ(histograms.size(), 400u);
  EXPECT_EQ(histograms.width, 400u);
  EXPECT_FALSE(histograms.is_dense);
  std::size_t nan = 0;
  for (std::size_t p = 0; p < 400; ++p)
    for (int b = 0; b < 64; ++b)
      nan += std::isnan(histograms[p].histogram[b]);
  EXPECT_EQ(nan, static_cast<std::size_t>(observed.size() - observed.count()));
  Eigen::MatrixXd back;
  ObservationMask back_observed;
  histogramsToPatches(histograms, back, back_observed);
  EXPECT_TRUE(back_observed == observed);
  EXPECT_TRUE((back.array() == patches.array()).all());  // float-representable: exact both ways
  EXPECT_TRUE(asHistograms(patches, ObservationMask()).is_dense);
  pcl::PointCloud<pcl::Histogram<256>> wrong;
  EXPECT_THROW(patchesToHistograms(patches, observed, wrong), Error);  // 64 bins into 256
}

TEST(PatchHistograms, LearnedFromHistogramsItIsTheDictionaryOfTheEquivalentMatrix)
{
  DictionaryLearningOptions options;
  options.num_atoms = 24;
  options.sparsity = 4;
  options.iterations = 6;
  options.seed = 3;
  for (const double hidden : {0.0, 0.3}) {
    Eigen::MatrixXd patches;
    ObservationMask observed;
    sparsePatches(hidden, patches, observed);
    auto histograms = asHistograms(patches, observed);
    PatchDictionary from_matrix;
    from_matrix.learn(patches, hidden > 0.0 ? observed : ObservationMask(), options);
    const PatchDictionary from_histograms = learnPatchDictionary(histograms, options);
    EXPECT_EQ(from_histograms.fingerprint(), from_matrix.fingerprint()) << "hidden " << hidden;
    EXPECT_EQ(from_histograms.numAtoms(), 24);
    EXPECT_EQ(from_histograms.learnedWith().iterations, 6);
    EXPECT_EQ(from_histograms.trainingPatches(), 400u);
    // A histogram without a finite bin (a seed without a frame) is left out: the same dictionary.
    histograms.push_back(Histogram64());
    std::fill_n(histograms.back().histogram, 64, std::numeric_limits<float>::quiet_NaN());
    EXPECT_EQ(learnPatchDictionary(histograms, options).fingerprint(), from_matrix.fingerprint());
  }
  pcl::PointCloud<Histogram64> only_nan(1, 1);
  std::fill_n(only_nan[0].histogram, 64, std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(learnPatchDictionary(only_nan, options), Error);
}

TEST(PatchHistograms, CodingHistogramsWithNaNBinsReproducesTheObservedOnesAndFillsTheRest)
{
  // The patches' own atoms as the dictionary: three atoms each, 30 % of the bins hidden.
  Eigen::MatrixXd patches, atoms, full;
  ObservationMask observed, all;
  sparsePatches(0.3, patches, observed, &atoms);
  sparsePatches(0.0, full, all);  // the same patches (same draws), every bin
  PatchDictionary dictionary;
  dictionary.setAtoms(atoms);
  const auto histograms = asHistograms(patches, observed);
  const PatchCodes codes = encodePatches(dictionary, histograms, {3, 0.0});
  pcl::PointCloud<Histogram64> decoded;
  decodePatches(dictionary, codes, decoded);
  ASSERT_EQ(decoded.size(), 400u);
  EXPECT_TRUE(decoded.is_dense);
  const double signal = std::sqrt(full.squaredNorm() / static_cast<double>(full.size()));
  EXPECT_LT(observedRMSE(decoded, histograms), 1e-5 * signal);
  // The hidden bins: against the full patches, where the histograms had NaN.
  double hidden_squared = 0.0;
  std::size_t hidden = 0;
  for (std::size_t p = 0; p < 400; ++p)
    for (int b = 0; b < 64; ++b)
      if (!observed(b, static_cast<Eigen::Index>(p))) {
        hidden_squared += std::pow(decoded[p].histogram[b] - full(b, static_cast<Eigen::Index>(p)), 2);
        ++hidden;
      }
  ASSERT_GT(hidden, 5000u);
  EXPECT_LT(std::sqrt(hidden_squared / static_cast<double>(hidden)), 0.01 * signal);
  // Every bin observed: Batch-OMP, the same codes as the matrix path.
  const PatchCodes dense = encodePatches(dictionary, asHistograms(full, ObservationMask()), {3, 0.0});
  const Eigen::MatrixXd matrix_codes(dictionary.encode(full, {3, 0.0}).coefficients);
  EXPECT_EQ((Eigen::MatrixXd(dense.coefficients) - matrix_codes).cwiseAbs().maxCoeff(), 0.0);
  pcl::PointCloud<pcl::Histogram<256>> wrong;
  EXPECT_THROW(decodePatches(dictionary, codes, wrong), Error);  // 64-bin atoms into 256 bins
}
