// The image-space depth denoiser on synthetic Kinect-like frames with known truth: σ(z) ∝ z² noise
// correlated between neighbouring pixels, depth quantised in 1/z, planes, a depth step and holes.
#include <pcl_patchdict/cloud/depth_image_denoising.h>
#include <pcl_patchdict/core/error.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace {

using pcl::patchdict::DepthDenoisingParameters;
using pcl::patchdict::DepthDenoisingReport;
using pcl::patchdict::DepthImage;
using pcl::patchdict::DepthNoiseModel;

const double kNaN = std::numeric_limits<double>::quiet_NaN();

DepthNoiseModel kinectNoise()
{
  DepthNoiseModel noise;
  noise.coefficient = 0.0012;  // 1.2 mm at 1 m
  noise.exponent = 2.0;
  return noise;
}

struct Frame {
  DepthImage image;
  std::vector<double> truth;  // NaN where nothing was measured
};

// A 200 × 150 frame (f = 525: the middle of a Kinect image) of the surface `depth_of`
// (column, row) → true depth; sensed with σ(z) noise whose neighbours correlate (white noise
// averaged over 3 × 3 pixels, then rescaled: ρ ≈ 0.67 at one pixel) and quantised in 1/z with steps
// of `step` at 1 m.
Frame sense(const std::function<double(int, int)>& depth_of, double step, unsigned seed)
{
  Frame frame;
  DepthImage& image = frame.image;
  const int W = 200, H = 150;
  image.width = W;
  image.height = H;
  image.camera.fx = image.camera.fy = 525.0;
  image.camera.cx = 99.5;
  image.camera.cy = 74.5;
  image.camera.valid = true;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> white(static_cast<std::size_t>(W + 2) * (H + 2));
  for (double& w : white)
    w = gauss(rng);
  const DepthNoiseModel noise = kinectNoise();
  image.depth.assign(static_cast<std::size_t>(W) * H, kNaN);
  image.valid.assign(image.depth.size(), 0);
  frame.truth.assign(image.depth.size(), kNaN);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const double z = depth_of(u, v);
      if (!(z > 0.0))
        continue;
      double e = 0.0;
      for (int dv = 0; dv < 3; ++dv)
        for (int du = 0; du < 3; ++du)
          e += white[static_cast<std::size_t>(v + dv) * (W + 2) + (u + du)];
      e /= 3.0;  // unit variance
      double sensed = z + noise.sigma(z) * e;
      if (step > 0.0)
        sensed = 1.0 / (std::round(1.0 / (sensed * step)) * step);  // layers evenly spaced in 1/z
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      image.depth[i] = sensed;
      image.valid[i] = 1;
      frame.truth[i] = z;
    }
  return frame;
}

// A plane n·x = d seen through the frame's camera: depth along pixel (u, v)'s ray.
std::function<double(int, int)> plane(const Eigen::Vector3d& normal, double distance)
{
  const Eigen::Vector3d n = normal.normalized();
  return [n, distance](int u, int v) {
    const Eigen::Vector3d ray((u - 99.5) / 525.0, (v - 74.5) / 525.0, 1.0);
    return distance / n.dot(ray);
  };
}

double rmsError(const std::vector<double>& depth, const Frame& frame, int margin = 0)
{
  double sum = 0.0;
  std::size_t count = 0;
  const int W = static_cast<int>(frame.image.width), H = static_cast<int>(frame.image.height);
  for (int v = margin; v < H - margin; ++v)
    for (int u = margin; u < W - margin; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * W + u;
      if (!frame.image.valid[i])
        continue;
      sum += (depth[i] - frame.truth[i]) * (depth[i] - frame.truth[i]);
      ++count;
    }
  return std::sqrt(sum / static_cast<double>(count));
}

TEST(DepthImageDenoising, ReducesCorrelatedQuantisedNoiseOnASlantedPlane)
{
  // Depth from ~0.8 m (top) to ~1.6 m (bottom): the plane is seen at up to ~60° from its normal.
  const Frame frame = sense(plane(Eigen::Vector3d(0.0, -0.7, 1.0), 1.0), 0.0006, 1);
  std::vector<double> out;
  DepthDenoisingReport report;
  pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), DepthDenoisingParameters(), out, report);
  ASSERT_EQ(out.size(), frame.image.depth.size());
  const double before = rmsError(frame.image.depth, frame, 0), after = rmsError(out, frame, 0);
  EXPECT_LT(after, 0.45 * before) << before << " → " << after;
  // Away from the image border the windows are whole: the error drops further.
  EXPECT_LT(rmsError(out, frame, 12), 0.4 * rmsError(frame.image.depth, frame, 12));
  EXPECT_EQ(report.measured, frame.image.measured());
  EXPECT_EQ(report.left, 0u);
  EXPECT_GT(report.moved, report.measured * 9 / 10);
  EXPECT_GE(report.radius_min, 2);
  EXPECT_LE(report.radius_max, 12);
  EXPECT_GE(report.radius_near, report.radius_far);  // fewer pixels cover the window far away
  EXPECT_GT(report.depth_far, report.depth_near);
  EXPECT_GT(report.rms_shift_sigmas, 0.5);
  EXPECT_LT(report.rms_shift_sigmas, 1.5);
  EXPECT_GE(report.seconds, 0.0);
  // No move beyond the clamp.
  for (std::size_t i = 0; i < out.size(); ++i)
    EXPECT_LE(std::abs(out[i] - frame.image.depth[i]), 4.0 * kinectNoise().sigma(frame.image.depth[i]) * (1 + 1e-9));
}

TEST(DepthImageDenoising, KeepsADepthStepSharp)
{
  // A box face 4 cm in front of a wall at 1 m: a 1.2 mm-noise scene's step of ~33 σ.
  const auto scene = [](int u, int v) { return (u >= 60 && u < 140 && v >= 40 && v < 110) ? 0.96 : 1.0; };
  const Frame frame = sense(scene, 0.0006, 2);
  std::vector<double> out;
  DepthDenoisingReport report;
  pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), DepthDenoisingParameters(), out, report);
  const double sigma = kinectNoise().sigma(1.0);
  double near_edge = 0.0, near_edge_input = 0.0;
  std::size_t count = 0;
  for (int v = 30; v < 120; ++v)
    for (int u = 50; u < 150; ++u) {
      const bool edge_column = (u >= 57 && u < 63) || (u >= 137 && u < 143);
      const bool edge_row = (v >= 37 && v < 43) || (v >= 107 && v < 113);
      if (!edge_column && !edge_row)
        continue;
      const std::size_t i = static_cast<std::size_t>(v) * 200 + u;
      // No point between the two surfaces: each stays within 3 σ of its own surface.
      EXPECT_LT(std::abs(out[i] - frame.truth[i]), 3.0 * sigma) << u << "," << v;
      near_edge += (out[i] - frame.truth[i]) * (out[i] - frame.truth[i]);
      near_edge_input += (frame.image.depth[i] - frame.truth[i]) * (frame.image.depth[i] - frame.truth[i]);
      ++count;
    }
  ASSERT_GT(count, 1000u);
  // And the pixels at the step are denoised too (from their own side of it).
  EXPECT_LT(std::sqrt(near_edge / count), 0.6 * std::sqrt(near_edge_input / count));
}

TEST(DepthImageDenoising, HolesStayHolesAndUnsupportedPixelsKeepTheirDepth)
{
  Frame frame = sense(plane(Eigen::Vector3d(0.2, -0.3, 1.0), 1.1), 0.0, 3);
  // A hole of 40 × 40 pixels with one lone measured pixel in its middle.
  for (int v = 50; v < 90; ++v)
    for (int u = 80; u < 120; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * 200 + u;
      frame.image.depth[i] = kNaN;
      frame.image.valid[i] = 0;
    }
  const std::size_t lone = static_cast<std::size_t>(70) * 200 + 100;
  frame.image.depth[lone] = 1.234;
  frame.image.valid[lone] = 1;
  std::vector<double> out;
  DepthDenoisingReport report;
  pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), DepthDenoisingParameters(), out, report);
  for (std::size_t i = 0; i < out.size(); ++i)
    EXPECT_EQ(std::isnan(out[i]), frame.image.valid[i] == 0) << i;
  EXPECT_EQ(out[lone], 1.234);
  EXPECT_EQ(report.left, 1u);
  EXPECT_EQ(report.measured, frame.image.measured());
}

TEST(DepthImageDenoising, DoesNotDependOnTheThreadCount)
{
  const Frame frame = sense(plane(Eigen::Vector3d(0.3, -0.5, 1.0), 1.2), 0.0006, 4);
  DepthDenoisingParameters parameters;
  std::vector<double> one, three;
  DepthDenoisingReport a, b;
  parameters.num_threads = 1;
  pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), parameters, one, a);
  parameters.num_threads = 3;
  pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), parameters, three, b);
  ASSERT_EQ(one.size(), three.size());
  for (std::size_t i = 0; i < one.size(); ++i)
    if (!(std::isnan(one[i]) && std::isnan(three[i]))) {
      ASSERT_EQ(one[i], three[i]) << i;
    }
  EXPECT_EQ(a.moved, b.moved);
  EXPECT_EQ(a.left, b.left);
  EXPECT_EQ(a.clamped, b.clamped);
  // The report too, to the last bit (it is written to --json): the RMS shift was an OpenMP
  // reduction of doubles, whose order followed the threads.
  EXPECT_EQ(a.rms_shift_sigmas, b.rms_shift_sigmas);
  EXPECT_GT(a.rms_shift_sigmas, 0.0);
}

TEST(DepthImageDenoising, WindowRadiusFollowsItsLaw)
{
  pcl::patchdict::PinholeCamera camera;
  camera.fx = camera.fy = 500.0;
  camera.valid = true;
  DepthDenoisingParameters parameters;  // 2 cm at 1 m, ∝ √z in metres
  EXPECT_EQ(pcl::patchdict::depthDenoisingRadius(camera, parameters, 1.0), 10);  // 0.02 m / 2 mm
  EXPECT_EQ(pcl::patchdict::depthDenoisingRadius(camera, parameters, 4.0), 5);   // 0.04 m / 8 mm
  EXPECT_EQ(pcl::patchdict::depthDenoisingRadius(camera, parameters, 0.25), 12); // 40 px, capped
  EXPECT_EQ(pcl::patchdict::depthDenoisingRadius(camera, parameters, 100.0), 2); // floor
  parameters.window_exponent = 1.0;  // a constant pixel radius
  EXPECT_EQ(pcl::patchdict::depthDenoisingRadius(camera, parameters, 0.5), 10);
  EXPECT_EQ(pcl::patchdict::depthDenoisingRadius(camera, parameters, 3.0), 10);
}

TEST(DepthImageDenoising, RefusesAnImageWithoutCameraOrNoise)
{
  Frame frame = sense(plane(Eigen::Vector3d(0.0, 0.0, 1.0), 1.0), 0.0, 5);
  std::vector<double> out;
  DepthDenoisingReport report;
  EXPECT_THROW(pcl::patchdict::denoiseDepthImage(frame.image, DepthNoiseModel(), DepthDenoisingParameters(), out, report),
               pcl::patchdict::Error);
  // A window reaching more than 32 samples from its pixel (the kernel's per-column tables).
  DepthDenoisingParameters wide;
  wide.max_radius = 66;
  wide.window_stride = 2;
  EXPECT_THROW(pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), wide, out, report), pcl::patchdict::Error);
  wide.max_radius = 64;  // 32 samples each side: allowed
  EXPECT_NO_THROW(pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), wide, out, report));
  wide.max_radius = 12;  // a minimum above the maximum is the reach that counts
  wide.min_radius = 80;
  EXPECT_THROW(pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), wide, out, report), pcl::patchdict::Error);
  frame.image.camera.valid = false;
  EXPECT_THROW(pcl::patchdict::denoiseDepthImage(frame.image, kinectNoise(), DepthDenoisingParameters(), out, report),
               pcl::patchdict::Error);
}

}  // namespace
