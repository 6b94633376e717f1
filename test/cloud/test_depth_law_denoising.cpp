// detail::denoiseCloud with per-point scales (a depth sensor's noise law): a synthetic depth image of
// a tilted plane seen from 1 to 2.6 m with σ(z) = a·z² along the view, white or correlated between
// neighbouring pixels; known answers on the per-point σ and h, the risk's correlation, outliers.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/search/kdtree.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace pcl {
namespace patchdict {
namespace {

constexpr std::size_t kW = 160, kH = 120;
constexpr double kF = 150.0, kA = 2e-3;  // focal length (pixels), σ(z) = kA · z²

double planeDepth(double column, double row)
{
  (void)column;
  // A plane seen in perspective is affine in 1/z: 1 m at the top row, 2.6 m at the bottom one.
  return 1.0 / (1.0 - (1.0 - 1.0 / 2.6) * row / static_cast<double>(kH - 1));
}

struct Frame {
  std::vector<Eigen::Vector3d> points, truth;
  std::vector<std::size_t> queries;
  detail::PointScales scales;
};

// Noise along each pixel's ray of σ(z); `correlated`: white noise averaged over 3 × 3 pixels and
// rescaled to the same σ (neighbouring pixels then share 2/3 and 1/3 of their noise, as block
// matching does). `spikes`: that many pixels moved by 10 σ(z) along the plane's normal (beyond the
// residual test's floor of two spacings too: σ(z) / s(z) = 0.3 z here).
Frame makeFrame(bool correlated, std::size_t spikes, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> white(kW * kH), noise(kW * kH);
  for (double& w : white)
    w = gauss(rng);
  for (std::size_t r = 0; r < kH; ++r)
    for (std::size_t c = 0; c < kW; ++c) {
      if (!correlated) {
        noise[r * kW + c] = white[r * kW + c];
        continue;
      }
      double sum = 0.0;
      int count = 0;
      for (std::size_t rr = r ? r - 1 : 0; rr <= std::min(kH - 1, r + 1); ++rr)
        for (std::size_t cc = c ? c - 1 : 0; cc <= std::min(kW - 1, c + 1); ++cc) {
          sum += white[rr * kW + cc];
          ++count;
        }
      noise[r * kW + c] = sum / std::sqrt(static_cast<double>(count));
    }
  Frame frame;
  const double cx = 0.5 * (kW - 1), cy = 0.5 * (kH - 1);
  for (std::size_t r = 0; r < kH; ++r)
    for (std::size_t c = 0; c < kW; ++c) {
      const double z = planeDepth(double(c), double(r));
      const Eigen::Vector3d ray((double(c) - cx) / kF, (double(r) - cy) / kF, 1.0);
      const double zn = z + kA * z * z * noise[r * kW + c];
      frame.truth.push_back(z * ray);
      frame.points.push_back(zn * ray);
      frame.queries.push_back(r * kW + c);
      frame.scales.sigma.push_back(kA * z * z);
      frame.scales.spacing.push_back(z / kF);
    }
  std::uniform_int_distribution<std::size_t> pick(kW * 2, kW * kH - kW * 2);
  const Eigen::Vector3d a = frame.truth[0], b = frame.truth[kW - 1], c = frame.truth[(kH - 1) * kW];
  const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
  for (std::size_t k = 0; k < spikes; ++k) {
    const std::size_t i = pick(rng);
    frame.points[i] += 10.0 * kA * frame.truth[i].z() * frame.truth[i].z() * normal;  // 10 σ(z) off the plane
  }
  return frame;
}

struct Result {
  std::vector<char> kept;
  std::vector<Eigen::Vector3d> positions, normals;
  CloudRepairReport report;
};

Result denoise(const Frame& frame, const CloudRepairParameters& parameters, bool with_scales)
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (const auto& p : frame.points)
    cloud->push_back(pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())));
  pcl::search::KdTree<pcl::PointXYZ> tree(true);
  tree.setInputCloud(cloud);
  const detail::KnnSearch knn = [&](std::size_t q, int k, pcl::Indices& found, std::vector<float>& squared) {
    tree.nearestKSearch((*cloud)[q], k, found, squared);
  };
  const RadiusNeighbourSearch radius = [&](std::size_t q, double r, int max_nn, pcl::Indices& found,
                                           std::vector<float>& squared) {
    tree.radiusSearch((*cloud)[q], r, found, squared, static_cast<unsigned int>(max_nn));
  };
  Result result;
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  detail::denoiseCloud(frame.points, {}, frame.queries, knn, radius, parameters, true, &origin, result.kept,
                       result.positions, result.normals, result.report, with_scales ? &frame.scales : nullptr);
  return result;
}

// RMS distance to the true plane in units of σ(z), over the kept points of rows [r0, r1) away from
// the image's rim (the rim's one-sided patches are another matter).
double relativeError(const Frame& frame, const Result& result, std::size_t r0, std::size_t r1)
{
  const Eigen::Vector3d a = frame.truth[0], b = frame.truth[kW - 1], c = frame.truth[(kH - 1) * kW];
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t r = r0; r < r1; ++r)
    for (std::size_t col = 12; col + 12 < kW; ++col) {
      const std::size_t i = r * kW + col;
      if (!result.kept[i])
        continue;
      const double d = n.dot(result.positions[i] - a) / (kA * frame.truth[i].z() * frame.truth[i].z());
      sum += d * d;
      ++count;
    }
  return std::sqrt(sum / static_cast<double>(std::max<std::size_t>(count, 1)));
}

}  // namespace

TEST(DepthLawDenoising, PerPointSigmaAndSpacingSmoothNearAndFarAlike)
{
  const Frame frame = makeFrame(false, 0, 7);
  CloudRepairParameters parameters;
  const Result result = denoise(frame, parameters, true);
  const CloudRepairReport& report = result.report;
  EXPECT_TRUE(report.depth_law);
  EXPECT_FALSE(report.noise_estimated);
  // σ reported: the median σ_i; h: the median h_i = factor × s_i.
  std::vector<double> sigmas = frame.scales.sigma, spacings = frame.scales.spacing;
  std::nth_element(sigmas.begin(), sigmas.begin() + long(sigmas.size() / 2), sigmas.end());
  std::nth_element(spacings.begin(), spacings.begin() + long(spacings.size() / 2), spacings.end());
  EXPECT_NEAR(report.noise_sigma, sigmas[sigmas.size() / 2], 1e-12);
  EXPECT_NEAR(report.bandwidth, report.bandwidth_factor * spacings[spacings.size() / 2], 1e-9);
  EXPECT_EQ(report.bandwidth_risks.size(), parameters.bandwidth_candidates.size());
  EXPECT_EQ(report.output_points, kW * kH);
  // Each point's error in its own σ(z): the far rows (σ 4× the near ones', spacing 2×) are
  // smoothed as much as the near ones, and both well below the noise.
  const double near = relativeError(frame, result, 12, 40), far = relativeError(frame, result, 80, kH - 12);
  EXPECT_LT(near, 0.2);
  EXPECT_LT(far, 0.2);
  EXPECT_LT(std::max(near, far) / std::min(near, far), 2.0);
  // White noise: no correlation measured beyond the first spacing.
  ASSERT_GE(report.noise_correlation.size(), 4u);
  EXPECT_LT(report.noise_correlation[2], 0.15);
  EXPECT_LT(report.correlation_sum, 1.6);
}

TEST(DepthLawDenoising, CorrelatedNoiseIsMeasuredAndWeighsInTheRisk)
{
  CloudRepairParameters parameters;
  const Result white = denoise(makeFrame(false, 0, 11), parameters, true);
  const Frame frame = makeFrame(true, 0, 11);
  const Result correlated = denoise(frame, parameters, true);
  // Neighbours one pixel apart share 2/3 (along a row) or 4/9 (diagonally) of their noise.
  EXPECT_GT(correlated.report.noise_correlation[2], 0.3);
  EXPECT_GT(correlated.report.correlation_sum, white.report.correlation_sum + 1.0);
  // The risk's leverage term grows with κ: at the smallest candidate it outweighs the residuals.
  EXPECT_GT(correlated.report.bandwidth_risks.front().risk, white.report.bandwidth_risks.front().risk);
  EXPECT_LT(relativeError(frame, correlated, 12, kH - 12), 0.35);
}

TEST(DepthLawDenoising, ResidualOutliersAreJudgedByTheirOwnSigma)
{
  const Frame frame = makeFrame(false, 40, 3);
  CloudRepairParameters parameters;
  parameters.outlier_filter = false;  // the residual test alone
  const Result result = denoise(frame, parameters, true);
  std::size_t spikes_kept = 0;
  for (std::size_t i = 0; i < frame.points.size(); ++i)
    if ((frame.points[i] - frame.truth[i]).norm() > 9.0 * kA * frame.truth[i].z() * frame.truth[i].z() && result.kept[i])
      ++spikes_kept;
  EXPECT_EQ(spikes_kept, 0u);
  EXPECT_GE(result.report.residual_removed, 38u);  // two spikes may land on the same pixel
  EXPECT_LT(result.report.residual_removed, 60u);  // and few Gaussian points beyond 4 σ_i
}

TEST(DepthLawDenoising, GivenSigmaOverridesTheLawAndBadScalesAreRefused)
{
  Frame frame = makeFrame(false, 0, 5);
  CloudRepairParameters parameters;
  parameters.noise_sigma = 0.004;
  parameters.bandwidth_candidates = {3.0};
  const Result result = denoise(frame, parameters, true);
  EXPECT_DOUBLE_EQ(result.report.noise_sigma, 0.004);
  EXPECT_DOUBLE_EQ(result.report.bandwidth_factor, 3.0);
  // Without scales: the global path (σ estimated from the residuals, no depth law).
  const Result global = denoise(frame, CloudRepairParameters{}, false);
  EXPECT_FALSE(global.report.depth_law);
  EXPECT_TRUE(global.report.noise_estimated);
  EXPECT_TRUE(global.report.noise_correlation.empty());
  frame.scales.sigma.pop_back();
  EXPECT_THROW(denoise(frame, CloudRepairParameters{}, true), Error);
  frame.scales.sigma.push_back(0.0);
  EXPECT_THROW(denoise(frame, CloudRepairParameters{}, true), Error);
}

}  // namespace patchdict
}  // namespace pcl
