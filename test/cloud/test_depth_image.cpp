// Depth images of organised clouds: the fitted camera, the noise law, the free-space test and the
// in-place fill, on synthetic Kinect-like frames (σ ∝ z², depth quantised in 1/z) with known truth.
#include "test_support.h"

#include <pcl_patchdict/cloud/depth_image.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/organized_hole_filling.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

namespace {

using pcl::patchdict::DepthImage;
using pcl::patchdict::DepthNoiseModel;
using pcl::patchdict::OrganizedFillParameters;
using pcl::patchdict::OrganizedFillReport;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

test_support::SyntheticFrame slantedWall(double noise, double step, unsigned seed)
{
  test_support::SyntheticFrame frame(160, 120, 150.0, 79.3, 60.2);
  frame.addPlane(Eigen::Vector3d(0.0, -0.8, 1.0), 1.2);  // depth from ~0.9 (top) to ~1.8 (bottom)
  frame.sense(noise, step, seed);
  return frame;
}

TEST(DepthImage, FitsTheCameraOfAFrameAndSetsAsideOffRayPoints)
{
  auto frame = slantedWall(0.0012, 0.0, 1);
  std::size_t wild = 0;
  for (std::size_t i = 0; i < frame.points.size(); i += 7)
    if (frame.points[i].allFinite()) {
      frame.points[i].z() = 1e30;  // a depth no sensor measured, x and y left as they were
      ++wild;
    }
  const DepthImage image = pcl::patchdict::makeDepthImage(frame.points, frame.width, frame.height);
  ASSERT_TRUE(image.camera.valid);
  EXPECT_NEAR(image.camera.fx, 150.0, 1e-3);
  EXPECT_NEAR(image.camera.fy, 150.0, 1e-3);
  EXPECT_NEAR(image.camera.cx, 79.3, 1e-3);
  EXPECT_NEAR(image.camera.cy, 60.2, 1e-3);
  EXPECT_LT(image.camera.rms_pixels, 1e-3);  // the wild depths stay out of the fit
  EXPECT_EQ(image.camera.off_ray, wild);
  EXPECT_EQ(image.measured(), frame.points.size() - wild);

  // The same points shuffled over the grid are no pinhole image.
  auto shuffled = frame.points;
  std::mt19937 rng(3);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  EXPECT_FALSE(pcl::patchdict::makeDepthImage(shuffled, frame.width, frame.height).camera.valid);
  // Nor is a frame whose finite points are all one point.
  std::vector<Eigen::Vector3d> same(frame.points.size(), Eigen::Vector3d(0.1, 0.2, 1.0));
  EXPECT_FALSE(pcl::patchdict::makeDepthImage(same, frame.width, frame.height).camera.valid);
}

TEST(DepthImage, NoiseLawOfAStructuredLightSensorIsRecovered)
{
  // σ = 1.5e-3 z²: Gaussian only, then with Kinect-like quantisation of 1/z (layers are noise).
  const auto clean = slantedWall(0.0015, 0.0, 2);
  const DepthNoiseModel law = pcl::patchdict::estimateDepthNoise(
      pcl::patchdict::makeDepthImage(clean.points, clean.width, clean.height));
  ASSERT_TRUE(law.exponent_fitted);
  EXPECT_NEAR(law.exponent, 2.0, 0.3);
  EXPECT_NEAR(law.sigma(1.0), 0.0015, 0.0003);
  EXPECT_NEAR(law.sigma(1.6), 0.0015 * 1.6 * 1.6, 0.0006);
  EXPECT_GT(law.depth_high, 1.5 * law.depth_low);

  const auto quantised = slantedWall(0.0015, 0.00285, 2);
  const DepthNoiseModel layered = pcl::patchdict::estimateDepthNoise(
      pcl::patchdict::makeDepthImage(quantised.points, quantised.width, quantised.height));
  // Quantisation adds step²/12 of variance (0.82e-3 z²): σ_eff ≈ 1.7e-3 z², never 0.
  EXPECT_GT(layered.sigma(1.0), 0.0015);
  EXPECT_LT(layered.sigma(1.0), 0.0025);
}

TEST(DepthImage, FreeSpaceIsWhatTheSensorSawThrough)
{
  const auto frame = slantedWall(0.0, 0.0, 4);
  const DepthImage image = pcl::patchdict::makeDepthImage(frame.points, frame.width, frame.height);
  const pcl::patchdict::FreeSpaceTest test(image);
  const Eigen::Vector3d wall = frame.points[60 * 160 + 80];
  EXPECT_TRUE(test.violates(0.9 * wall));    // 10 % in front of a measured wall
  EXPECT_FALSE(test.violates(1.1 * wall));   // behind it: unseen
  EXPECT_FALSE(test.violates(0.999 * wall)); // within the tolerance
  EXPECT_FALSE(test.violates(Eigen::Vector3d(0.0, 0.0, -1.0)));  // behind the camera
  EXPECT_FALSE(test.violates(Eigen::Vector3d(50.0, 0.0, 1.0)));  // outside the image
}

// The seen depth of a pixel is the minimum of the measured depths of its 3 × 3 neighbourhood (it is
// computed as a minimum over columns, then over rows, in bands of rows per thread): checked against
// that definition pixel by pixel on a random image with unmeasured pixels, NaN depths and odd sizes.
TEST(DepthImage, FreeSpaceSeesTheNearestMeasuredDepthOfEachNeighbourhood)
{
  for (const auto& [W, H] : {std::pair<std::size_t, std::size_t>{37, 23}, {1, 9}, {9, 1}, {2, 2}}) {
    DepthImage image;
    image.width = W;
    image.height = H;
    image.camera.fx = image.camera.fy = 50.0;
    image.camera.cx = 0.5 * (W - 1.0);
    image.camera.cy = 0.5 * (H - 1.0);
    image.camera.valid = true;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> depth(1.0, 2.0), coin(0.0, 1.0);
    image.depth.resize(W * H);
    image.valid.resize(W * H);
    for (std::size_t i = 0; i < W * H; ++i) {
      image.valid[i] = coin(rng) < 0.7;
      image.depth[i] = coin(rng) < 0.05 ? kNaN : depth(rng);  // NaN even where marked valid: never seen
    }
    const pcl::patchdict::FreeSpaceTest test(image, 0.0, 0.001);  // tolerance 0.1 % of the seen depth
    for (std::size_t r = 0; r < H; ++r)
      for (std::size_t c = 0; c < W; ++c) {
        double seen = std::numeric_limits<double>::infinity();
        for (std::size_t rr = r ? r - 1 : 0; rr <= std::min(H - 1, r + 1); ++rr)
          for (std::size_t cc = c ? c - 1 : 0; cc <= std::min(W - 1, c + 1); ++cc)
            if (image.valid[rr * W + cc] && std::isfinite(image.depth[rr * W + cc]))
              seen = std::min(seen, image.depth[rr * W + cc]);
        const auto at = [&](double z) { return image.camera.pointAt(double(c), double(r), z); };
        const std::size_t i = r * W + c;
        if (!std::isfinite(seen)) {
          EXPECT_FALSE(test.violates(at(0.5))) << W << "x" << H << " " << c << "," << r;
          EXPECT_FALSE(test.violatesAt(i, 0.5)) << W << "x" << H << " " << c << "," << r;
          continue;
        }
        EXPECT_TRUE(test.violates(at(seen * 0.998))) << W << "x" << H << " " << c << "," << r;
        EXPECT_FALSE(test.violates(at(seen * 0.9995))) << W << "x" << H << " " << c << "," << r;
        // On the pixel's own ray, without projecting: the same answers.
        EXPECT_TRUE(test.violatesAt(i, seen * 0.998)) << W << "x" << H << " " << c << "," << r;
        EXPECT_FALSE(test.violatesAt(i, seen * 0.9995)) << W << "x" << H << " " << c << "," << r;
        EXPECT_FALSE(test.violatesAt(i, -seen)) << W << "x" << H << " " << c << "," << r;
      }
  }
}

TEST(OrganizedHoleFilling, FillsAHoleOnOneSurfaceAndNeverBridgesAShadow)
{
  test_support::SyntheticFrame frame(160, 120, 150.0, 79.3, 60.2);
  frame.addPlane(Eigen::Vector3d(0.2, -0.3, 1.0), 1.2);
  frame.addBox(100, 140, 20, 100, 0.7);  // a box in front, its shadow a NaN strip on its left
  const auto truth = frame.depth;
  frame.sense(0.0012, 0.00285, 5);
  frame.erase(94, 100, 25, 95);          // the shadow: between the box (0.7 m) and the wall (~1.2 m)
  frame.eraseDisc(40, 60, 8);            // a dropout on the wall
  frame.eraseDisc(2, 10, 5);             // one at the image border: not enclosed
  const DepthImage image = pcl::patchdict::makeDepthImage(frame.points, frame.width, frame.height);
  ASSERT_TRUE(image.camera.valid);
  const DepthNoiseModel law = pcl::patchdict::estimateDepthNoise(image);
  std::vector<std::size_t> pixels;
  std::vector<Eigen::Vector3d> points;
  OrganizedFillReport report;
  pcl::patchdict::fillOrganizedHoles(image, law, OrganizedFillParameters{}, pixels, points, report);
  EXPECT_EQ(report.holes_filled, 1u);
  EXPECT_GE(report.not_one_surface, 1u);
  EXPECT_GE(report.touching_border, 1u);
  EXPECT_EQ(report.free_space_dropped, 0u);
  ASSERT_EQ(pixels.size(), frame.disc(40, 60, 8).size());
  double error = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    const std::size_t i = pixels[k], column = i % frame.width, row = i / frame.width;
    EXPECT_LT((column - 40.0) * (column - 40.0) + (row - 60.0) * (row - 60.0), 65.0);  // only the disc
    const Eigen::Vector2d pixel = image.camera.project(points[k]);
    EXPECT_NEAR(pixel.x(), static_cast<double>(column), 1e-6);  // on its own pixel's ray
    EXPECT_NEAR(pixel.y(), static_cast<double>(row), 1e-6);
    error += std::abs(points[k].z() - truth[i]);
    worst = std::max(worst, std::abs(points[k].z() - truth[i]));
  }
  const double sigma = law.sigma(1.2);
  EXPECT_LT(error / static_cast<double>(pixels.size()), 1.5 * sigma);  // the wall, not its noise
  EXPECT_LT(worst, 5.0 * sigma);

  // Larger than allowed: stays open.
  OrganizedFillParameters small;
  small.max_hole_pixels = 100;
  OrganizedFillReport bounded;
  pixels.clear();
  points.clear();
  pcl::patchdict::fillOrganizedHoles(image, law, small, pixels, points, bounded);
  EXPECT_EQ(bounded.holes_filled, 0u);
  EXPECT_GE(bounded.too_large, 1u);
  EXPECT_TRUE(pixels.empty());

  small.rim_outlier_share = 2.0;
  EXPECT_THROW(pcl::patchdict::fillOrganizedHoles(image, law, small, pixels, points, bounded), pcl::patchdict::Error);
}

}  // namespace
