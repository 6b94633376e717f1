// Non-local patch averaging (nonlocal_patch_denoising.h): it lowers the error of a noisy grooved relief
// below the geometric base's, is declined on a noisy smooth dome, and does not depend on the threads.
#include <pcl_patchdict/cloud/nonlocal_patch_denoising.h>
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
using pcl::patchdict::PatchOutcome;
using Inpainter = pcl::patchdict::SparsePatchInpainter<pcl::PointXYZ>;
using relief_test_shapes::Height;
using relief_test_shapes::dome;
using relief_test_shapes::grooves;

/** 40,000 uniform samples of z = height(x, y) over [-0.25, 0.25]² (mean spacing ≈ 0.00125), noise of
  * σ = 0.0006 in z. */
pcl::PointCloud<pcl::PointXYZ>::Ptr noisyCloud(const Height& height)
{
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> uniform(-0.25, 0.25);
  std::normal_distribution<double> noise(0.0, 0.0006);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  while (cloud->size() < 40000) {
    const double x = uniform(random), y = uniform(random);
    cloud->push_back(pcl::PointXYZ(static_cast<float>(x), static_cast<float>(y), static_cast<float>(height(x, y) + noise(random))));
  }
  return cloud;
}

struct Denoised {
  pcl::PointCloud<pcl::PointXYZ> out;
  pcl::patchdict::NonlocalPatchReport nonlocal;
  double rms = 0.0;  ///< rms |z − height(x, y)|, over the points away from the border
};

Denoised denoise(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud, const Height& height, PatchDecision decision)
{
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(Inpainter::Mode::Denoise);
  inpainter.setPatchDecision(decision);
  inpainter.setNumberOfThreads(2);
  Denoised d;
  inpainter.process(d.out);
  d.nonlocal = inpainter.getNonlocalPatchReport();
  std::size_t count = 0;
  for (const auto& p : d.out)
    if (std::abs(p.x) < 0.22 && std::abs(p.y) < 0.22) {
      const double e = p.z - height(p.x, p.y);
      d.rms += e * e;
      ++count;
    }
  d.rms = std::sqrt(d.rms / static_cast<double>(std::max<std::size_t>(count, 1)));
  return d;
}

TEST(NonlocalPatchDenoising, LowersTheErrorOfANoisyReliefBelowTheBase)
{
  const auto cloud = noisyCloud(grooves);
  const Denoised base = denoise(cloud, grooves, PatchDecision::Never);
  const Denoised nonlocal = denoise(cloud, grooves, PatchDecision::Always);
  EXPECT_EQ(base.nonlocal.outcome, PatchOutcome::Declined);
  ASSERT_EQ(nonlocal.nonlocal.outcome, PatchOutcome::Applied) << nonlocal.nonlocal.reason;
  EXPECT_LT(nonlocal.nonlocal.patch_error, nonlocal.nonlocal.base_error);  // the estimate, reported
  EXPECT_GT(nonlocal.nonlocal.z, 3.0);
  EXPECT_LT(nonlocal.rms, 0.85 * base.rms) << nonlocal.rms << " vs " << base.rms;
}

// The default (Auto) does not run the stage: its only check was measured to misjudge smooth scans.
TEST(NonlocalPatchDenoising, NotRunByDefault)
{
  const auto cloud = noisyCloud(dome);
  const Denoised base = denoise(cloud, dome, PatchDecision::Never);
  const Denoised automatic = denoise(cloud, dome, PatchDecision::Auto);
  EXPECT_EQ(automatic.nonlocal.outcome, PatchOutcome::Declined);
  EXPECT_NE(automatic.nonlocal.reason.find("not run unless forced"), std::string::npos) << automatic.nonlocal.reason;
  EXPECT_EQ(automatic.nonlocal.scored_points, 0u);
  ASSERT_EQ(automatic.out.size(), base.out.size());
  for (std::size_t i = 0; i < base.out.size(); ++i)
    ASSERT_EQ(automatic.out[i].getVector3fMap(), base.out[i].getVector3fMap()) << i;
}

TEST(NonlocalPatchDenoising, SameOutputWhateverTheThreadCount)
{
  const auto cloud = noisyCloud(grooves);
  std::vector<Eigen::Vector3d> noisy, base;
  for (const auto& p : *cloud) {
    noisy.emplace_back(p.x, p.y, p.z);
    base.emplace_back(p.x, p.y, grooves(p.x, p.y));  // any base will do
  }
  pcl::patchdict::NonlocalPatchOptions options;
  std::vector<Eigen::Vector3d> one, two;
  options.num_threads = 1;
  pcl::patchdict::averageSimilarPatches(noisy, base, 0.0, 0.0006, options, one);
  options.num_threads = 2;
  pcl::patchdict::averageSimilarPatches(noisy, base, 0.0, 0.0006, options, two);
  ASSERT_EQ(one.size(), two.size());
  std::size_t moved = 0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one[i], two[i]) << i;
    moved += one[i] != base[i];
  }
  EXPECT_GT(moved, one.size() / 2);
}

TEST(NonlocalPatchDenoising, BadOptionsAndInputAreOneClearError)
{
  using pcl::patchdict::Error;
  using pcl::patchdict::NonlocalPatchOptions;
  const auto bad = [](const std::function<void(NonlocalPatchOptions&)>& change) {
    NonlocalPatchOptions options;
    change(options);
    EXPECT_THROW(options.check(), Error);
  };
  bad([](NonlocalPatchOptions& o) { o.grid_size = 7; });
  bad([](NonlocalPatchOptions& o) { o.dimensions = 0; });
  bad([](NonlocalPatchOptions& o) { o.dimensions = 65; });
  bad([](NonlocalPatchOptions& o) { o.neighbours = 0; });
  bad([](NonlocalPatchOptions& o) { o.bandwidth_factor = -1.0; });
  bad([](NonlocalPatchOptions& o) { o.blind_radius = -0.5; });
  bad([](NonlocalPatchOptions& o) { o.blind_radius = 6.0; });
  bad([](NonlocalPatchOptions& o) { o.search_eps = std::nan(""); });
  bad([](NonlocalPatchOptions& o) { o.decision.min_risk_reduction = 1.0; });
  EXPECT_NO_THROW(NonlocalPatchOptions().check());
  std::vector<Eigen::Vector3d> points(300, Eigen::Vector3d::Zero()), fewer(299, Eigen::Vector3d::Zero()), out;
  EXPECT_THROW(pcl::patchdict::denoiseCloudNonlocally(points, fewer, 0.0, 0.1, 0.1, {}, out), Error);
  EXPECT_THROW(pcl::patchdict::denoiseCloudNonlocally(points, points, 0.0, -0.1, 0.1, {}, out), Error);
  points[7].x() = std::nan("");
  EXPECT_THROW(pcl::patchdict::averageSimilarPatches(points, points, 0.0, 0.1, {}, out), Error);
}

}  // namespace
