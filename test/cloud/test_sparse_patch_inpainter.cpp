// SparsePatchInpainter: patches correct the geometric fill of a relief cloud's holes, and leave a
// smooth cloud's fill exactly as the base made it.
#include <pcl_patchdict/cloud/cloud_patch_correction.h>
#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>
#include <pcl_patchdict/core/error.h>

#include "relief_test_shapes.h"

#include <gtest/gtest.h>

#include <pcl/point_types.h>

#include <cmath>
#include <functional>
#include <random>

namespace {

using pcl::patchdict::PatchDecision;
using Inpainter = pcl::patchdict::SparsePatchInpainter<pcl::PointXYZ>;
using relief_test_shapes::Height;
using relief_test_shapes::dome;
using relief_test_shapes::grooves;

/** 40,000 uniform samples of z = height(x, y) over [-0.25, 0.25]², without four discs of radius 0.03. */
pcl::PointCloud<pcl::PointXYZ>::Ptr holedCloud(const Height& height)
{
  const double centres[4][2] = {{-0.1, -0.1}, {0.1, -0.08}, {-0.07, 0.11}, {0.09, 0.1}};
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(-0.25, 0.25);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  while (cloud->size() < 40000) {
    const double x = uniform(random), y = uniform(random);
    bool in_hole = false;
    for (const auto& c : centres)
      in_hole = in_hole || std::hypot(x - c[0], y - c[1]) < 0.03;
    if (!in_hole)
      cloud->push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y), static_cast<float>(height(x, y))));
  }
  return cloud;
}

struct Fill {
  pcl::PointCloud<pcl::PointXYZ> out;
  pcl::patchdict::CloudPatchReport patches;
  std::size_t added = 0;
  double mean_error = 0.0;  ///< mean |z − height(x, y)| of the added points
};

Fill fill(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, const Height& height, PatchDecision decision, int threads = 2)
{
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(Inpainter::Mode::Complete);
  inpainter.setPatchDecision(decision);
  inpainter.setNumberOfThreads(threads);
  Fill f;
  inpainter.process(f.out);
  f.patches = inpainter.getPatchReport();
  f.added = inpainter.getReport().points_added;
  for (std::size_t i = f.out.size() - f.added; i < f.out.size(); ++i)
    f.mean_error += std::abs(f.out[i].z - height(f.out[i].x, f.out[i].y));
  f.mean_error /= static_cast<double>(std::max<std::size_t>(f.added, 1));
  return f;
}

TEST(SparsePatchInpainter, PatchesHalveTheErrorOfAReliefsHoleFillAndSayWhy)
{
  const auto cloud = holedCloud(grooves);
  const Fill base = fill(cloud, grooves, PatchDecision::Never);
  const Fill patches = fill(cloud, grooves, PatchDecision::Auto);
  ASSERT_GT(base.added, 1500u);  // four discs of radius 0.03 at the input's density: ~2,000 points
  EXPECT_EQ(patches.added, base.added);
  EXPECT_EQ(base.patches.outcome, pcl::patchdict::PatchOutcome::Declined);
  EXPECT_EQ(patches.patches.outcome, pcl::patchdict::PatchOutcome::Applied);
  EXPECT_EQ(patches.patches.holes, 4u);
  EXPECT_NEAR(patches.patches.hole_diameter, 0.06, 0.015);
  EXPECT_GT(patches.patches.gain, 1.3);  // the check's measurement, which decided
  EXPECT_LT(patches.patches.dictionary_rms, patches.patches.biharmonic_rms);
  EXPECT_EQ(patches.patches.moved_points, patches.added);
  // The smooth fill is off by about the grooves' mean depth; the patches bring the grooves back.
  EXPECT_GT(base.mean_error, 8e-4);
  EXPECT_LT(patches.mean_error, 0.5 * base.mean_error);
  // The input points are the base's, untouched.
  for (std::size_t i = 0; i < cloud->size(); ++i)
    ASSERT_EQ(patches.out[i].getVector3fMap(), (*cloud)[i].getVector3fMap());
}

TEST(SparsePatchInpainter, ASmoothCloudKeepsTheGeometricFillPointForPoint)
{
  const auto cloud = holedCloud(dome);
  const Fill base = fill(cloud, dome, PatchDecision::Never);
  const Fill automatic = fill(cloud, dome, PatchDecision::Auto);
  EXPECT_EQ(automatic.patches.outcome, pcl::patchdict::PatchOutcome::Declined);
  EXPECT_FALSE(automatic.patches.reason.empty());
  // The rule that declined: gain below 1.3, or an improvement under 0.1 spacings.
  EXPECT_TRUE(automatic.patches.gain < 1.3 || automatic.patches.biharmonic_rms - automatic.patches.dictionary_rms <
                                                  0.1 * automatic.patches.spacing)
      << automatic.patches.gain;
  ASSERT_EQ(automatic.out.size(), base.out.size());
  for (std::size_t i = 0; i < base.out.size(); ++i)
    ASSERT_EQ(automatic.out[i].getVector3fMap(), base.out[i].getVector3fMap()) << i;
  EXPECT_LT(base.mean_error, 1e-4);  // a dome is what a smooth fill is made for
}

TEST(SparsePatchInpainter, SameOutputWhateverTheThreadCount)
{
  const auto cloud = holedCloud(grooves);
  const Fill one = fill(cloud, grooves, PatchDecision::Always, 1);
  const Fill two = fill(cloud, grooves, PatchDecision::Always, 2);
  ASSERT_EQ(one.out.size(), two.out.size());
  for (std::size_t i = 0; i < one.out.size(); ++i)
    ASSERT_EQ(one.out[i].getVector3fMap(), two.out[i].getVector3fMap()) << i;
}

TEST(SparsePatchInpainter, BadPatchOptionsAreOneClearError)
{
  pcl::patchdict::CloudPatchOptions options;
  options.decision.quad_factor = -1.0;
  EXPECT_THROW(pcl::patchdict::checkCloudPatchOptions(options), pcl::patchdict::Error);
  options = {};
  options.decision.probe_factors.clear();
  EXPECT_THROW(pcl::patchdict::checkCloudPatchOptions(options), pcl::patchdict::Error);
  options = {};
  options.grid_size = 1;
  EXPECT_THROW(pcl::patchdict::checkCloudPatchOptions(options), pcl::patchdict::Error);
  EXPECT_NO_THROW(pcl::patchdict::checkCloudPatchOptions({}));
}

// The holes' diameter d sizes the patches: it is the median over the holes, and the sampling gaps a
// fill closes beside them (groups of a tenth of the largest group's points or fewer) are no holes —
// 13 small gaps must not outvote 3 real holes (they did: d fell to a gap's size, the patches shrank).
TEST(SparsePatchInpainter, TheHoleDiameterIgnoresClosedSamplingGaps)
{
  std::vector<Eigen::Vector3d> observed, added, corrected;
  const double s = 0.01;  // spacing
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      observed.emplace_back(i * s, j * s, 0.0);
  const auto disc = [&](double cx, double cy, double radius) {
    for (double x = -radius; x <= radius + 1e-12; x += 0.5 * s)
      for (double y = -radius; y <= radius + 1e-12; y += 0.5 * s)
        if (x * x + y * y <= radius * radius)
          added.emplace_back(cx + x, cy + y, 0.0);
  };
  for (int h = 0; h < 3; ++h)
    disc(0.2 + 0.3 * h, 0.3, 0.08);  // real holes: ~800 points, 0.16 across
  for (int g = 0; g < 13; ++g)
    disc(0.05 + 0.07 * g, 0.8, 0.01);  // closed gaps: ~13 points, 0.02 across
  pcl::patchdict::CloudPatchOptions options;
  options.decision.mode = PatchDecision::Never;  // d alone: the stage need not run
  pcl::patchdict::CloudPatchReport report;
  pcl::patchdict::correctCloudFillWithPatches(observed, added, s, options, corrected, &report);
  EXPECT_EQ(report.holes, 3u);
  EXPECT_NEAR(report.hole_diameter, 0.16, 0.01);
}

}  // namespace
