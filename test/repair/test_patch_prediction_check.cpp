// checkPatchPrediction: a relief is predictable from its own patches, white noise is not, and too
// little evidence gives no verdict.
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_decision.h>
#include <pcl_patchdict/repair/patch_prediction_check.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>


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

// The patch decision's own pieces (repair/patch_decision.h), shared by meshes and clouds.
TEST(PatchDecision, OptionsAreCheckedFieldByFieldAndOutcomesHaveTheirReportWords)
{
  EXPECT_NO_THROW(PatchDecisionOptions().check());
  const std::vector<std::function<void(PatchDecisionOptions&)>> bad = {
      [](auto& o) { o.probe_factors.clear(); },     [](auto& o) { o.probe_factors = {0.8, -1.0}; },
      [](auto& o) { o.probe_radius = 0.0; },        [](auto& o) { o.relief_gain = std::nan(""); },
      [](auto& o) { o.min_improvement = -0.1; },    [](auto& o) { o.probe_max_seeds = -1; },
      [](auto& o) { o.quad_factor = -0.5; },        [](auto& o) { o.min_risk_reduction = 1.0; }};
  for (std::size_t i = 0; i < bad.size(); ++i) {
    PatchDecisionOptions options;
    bad[i](options);
    EXPECT_THROW(options.check(), Error) << "case " << i;
  }
  EXPECT_STREQ(toString(PatchOutcome::NotRun), "not run");
  EXPECT_STREQ(toString(PatchOutcome::Applied), "applied");
  EXPECT_STREQ(toString(PatchOutcome::Declined), "declined");
  // The hidden disc: probe_radius × d, at most 0.3 × the side; the risk margin as a fraction.
  const PatchDecisionOptions o;
  EXPECT_DOUBLE_EQ(o.hiddenRadius(1.0, 10.0), 0.35);
  EXPECT_DOUBLE_EQ(o.hiddenRadius(1.0, 1.0), 0.3);
  EXPECT_TRUE(patchesLowerTheRisk(0.94, 1.0, o));
  EXPECT_FALSE(patchesLowerTheRisk(0.96, 1.0, o));
}

// The relief check over sides: on the repeating relief the dictionary's gain counts (relief); with a
// margin no prediction can clear, the same gain is only the best of all (shown, but no relief); white
// noise is no relief; nothing measured gives gain 0 and nothing to show.
TEST(PatchDecision, TheReliefCheckCountsAGainOnlyWithItsMargin)
{
  const PatchDecisionOptions options;
  const PatchCorrectionParameters parameters;
  const PatchSet relief = reliefPatches(0.0, 1), noise = reliefPatches(0.005, 2);
  const double d = 0.03 / options.probe_radius;  // a hidden disc of 0.03, as the checks above
  const auto verdictOn = [&](const PatchSet& set, double unit) {
    return checkRelief({set, set}, {set.side(), set.side()}, d, unit, options, nullptr, parameters);
  };
  const ReliefVerdict counted = verdictOn(relief, 1e-6);
  ASSERT_EQ(counted.checks.size(), 2u);
  EXPECT_TRUE(counted.relief(options)) << counted.best_significant;
  EXPECT_EQ(counted.significant_side, 0);  // the first of two equal gains
  EXPECT_EQ(counted.shown(), &counted.checks[0]);
  EXPECT_GT(counted.gain(), 2.0);
  const ReliefVerdict unclearable = verdictOn(relief, 1.0);
  EXPECT_FALSE(unclearable.relief(options));
  EXPECT_EQ(unclearable.significant_side, -1);
  EXPECT_EQ(unclearable.gain(), counted.gain());  // the best of all, shown as such
  EXPECT_EQ(unclearable.shown(), &unclearable.checks[0]);
  EXPECT_FALSE(verdictOn(noise, 1e-6).relief(options));
  const ReliefVerdict none = checkRelief({}, {}, d, 1.0, options, nullptr, parameters);
  EXPECT_EQ(none.gain(), 0.0);
  EXPECT_EQ(none.shown(), nullptr);
  EXPECT_THROW(checkRelief({relief}, {}, d, 1.0, options, nullptr, parameters), Error);
}
