// checkPatchPrediction: a relief is predictable from its own patches, white noise is not, and too
// little evidence gives no verdict.
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_prediction_check.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>


using namespace pcl::patchdict;

namespace {

PatchSet reliefPatches(double noise, std::uint64_t seed)
{
  // A relief without noise, or a plane with noise along its normal (z) and nothing to predict.
  const TriangleMesh relief =
      addNormalNoise(makeSinusoidalRelief(80, 80, noise > 0.0 ? 0.0 : 0.02, 0.15), noise, seed);
  PatchCorrectionParameters parameters;
  parameters.quad_length = 0.12;
  return PatchCorrection::trainingPatches(relief, parameters, 16);
}

}  // namespace

TEST(PatchPredictionCheck, ARepeatingReliefIsPredictedFarBetterThanByABiharmonicFill)
{
  const PatchSet patches = reliefPatches(0.0, 1);
  const PatchPredictionCheck check = checkPatchPrediction(patches, 0.03, nullptr, PatchCorrectionParameters{});
  ASSERT_GE(check.test_patches, 20u);
  EXPECT_GT(check.hidden_bins, 10u);
  RecordProperty("gain", std::to_string(check.gain));
  EXPECT_GT(check.gain, 2.0) << check.dictionary_rms << " vs " << check.biharmonic_rms;  // measured 3.40
}

TEST(PatchPredictionCheck, WhiteNoiseIsNotPredictable)
{
  const PatchSet patches = reliefPatches(0.005, 2);
  const PatchPredictionCheck check = checkPatchPrediction(patches, 0.03, nullptr, PatchCorrectionParameters{});
  ASSERT_GE(check.test_patches, 20u);
  RecordProperty("gain", std::to_string(check.gain));
  EXPECT_LT(check.gain, 1.2) << check.dictionary_rms << " vs " << check.biharmonic_rms;  // measured 0.94
}

TEST(PatchPredictionCheck, TooLittleEvidenceGivesNoVerdict)
{
  const PatchSet patches = reliefPatches(0.0, 3);
  EXPECT_EQ(checkPatchPrediction(patches, 0.03, nullptr, PatchCorrectionParameters{}, 100000).gain, 0.0);
  EXPECT_EQ(checkPatchPrediction(patches, 1e-6, nullptr, PatchCorrectionParameters{}).gain, 0.0);  // no bin hidden
  EXPECT_EQ(checkPatchPrediction(patches, 10.0, nullptr, PatchCorrectionParameters{}).gain, 0.0);  // all hidden
}
