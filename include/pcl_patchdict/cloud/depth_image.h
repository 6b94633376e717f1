// An organised cloud as the depth image it is: the pinhole camera fitted to its pixel grid, the
// sensor's depth-dependent noise σ(z) = a·z^p estimated from the scan, and the free-space test.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {

/** column = fx·x/z + cx, row = fy·y/z + cy: the camera of an organised cloud, z along the view. */
struct PinholeCamera {
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  bool valid = false;            ///< a fit was possible and the grid is a pinhole image
  double rms_pixels = 0.0;       ///< RMS reprojection error of the points used, in pixels
  std::size_t off_ray = 0;       ///< finite points farther than max_reprojection from their own pixel

  Eigen::Vector2d project(const Eigen::Vector3d& p) const { return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy}; }
  /** The point at depth z on the ray of pixel (column, row). */
  Eigen::Vector3d pointAt(double column, double row, double z) const
  {
    return {(column - cx) * z / fx, (row - cy) * z / fy, z};
  }
  /** Distance between neighbouring pixels' points on a plane facing the camera at depth z. */
  double pixelSpacing(double z) const { return z / std::sqrt(fx * fy); }
};

/** Points of an organised cloud that are on their own pixel's ray: finite, z > 0 and within
  * max_reprojection pixels of their cell once the camera is fitted. */
struct DepthImage {
  std::size_t width = 0, height = 0;
  PinholeCamera camera;
  std::vector<double> depth;  ///< z per pixel; NaN where the pixel holds no usable point
  std::vector<char> valid;    ///< 1 where depth is a measurement
  std::size_t measured() const;
  double at(std::size_t column, std::size_t row) const { return depth[row * width + column]; }
};

/** Fits the camera (robustly: medians of per-row and per-column slopes, then least squares over the
  * points within max_reprojection pixels) and builds the depth image. Points off their ray (e.g. a
  * depth of 1e30 written into a frame) are counted in camera.off_ray and left out of the image.
  * camera.valid is false when fewer than 16 points remain or the grid is no pinhole image (RMS
  * reprojection above max_reprojection / 2): the cloud is then handled as unorganised. A depth
  * beyond 1000× (or below 1/1000 of) the median depth counts as off its ray too. */
DepthImage makeDepthImage(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                          double max_reprojection = 1.5);

/** σ(z) = coefficient · z^exponent: the noise of depth along the view ray. Structured light and
  * stereo measure disparity, so σ grows as z² (Khoshelham & Elberink, Sensors 2012). */
struct DepthNoiseModel {
  double coefficient = 0.0;
  double exponent = 2.0;
  bool exponent_fitted = false;  ///< false: the scan's depths span too little to fit it; 2 assumed
  std::size_t samples = 0;       ///< planar 5 × 5 windows the estimate used
  double depth_low = 0.0, depth_high = 0.0;  ///< 5th and 95th percentiles of the sampled depths
  double sigma(double z) const;
};

/** Estimates the depth noise from the scan: in every 5 × 5 window (sampled on a stride) with at
  * least 16 measured neighbours, all within 5 % of the centre's depth, the centre's depth is
  * predicted by a plane fitted to them in 1/z over (column, row) — a plane seen in perspective is
  * affine in 1/z — and the residual, divided by √(1 + h) for the prediction's own variance (h its
  * leverage, 1/24 with every neighbour), is one sample.
  * Depth quantisation steps enter the residuals: they are noise, not detail. The exponent comes from
  * the medians of six depth bins (log-log slope, clamped to [0, 3]) when the 95th/5th depth ratio is
  * at least 1.5; the coefficient is 1.4826 × the median of |r| / z^p (robust to edges and corners). */
DepthNoiseModel estimateDepthNoise(const DepthImage& image, std::size_t stride = 2);

/** The sensor's free space: a point that projects onto a pixel of the image and lies in front of
  * the nearest measured depth among that pixel's 3 × 3 neighbours by more than
  * max(spacing_factor × pixel spacing, relative_depth × that depth) was seen through — it is wrong. */
class FreeSpaceTest {
public:
  explicit FreeSpaceTest(const DepthImage& image, double spacing_factor = 2.0, double relative_depth = 0.008);
  /** True when p lies in space the sensor saw through. Points behind the camera or outside the
    * image are not judged (false). */
  bool violates(const Eigen::Vector3d& p) const;
  /** The same test for a point on pixel i's own ray (row-major index) at depth z, without projecting
    * it: what violates(camera.pointAt(i % width, i / width, z)) answers. */
  bool violatesAt(std::size_t i, double z) const;

private:
  bool nearerThanSeen(double z, double seen) const;
  PinholeCamera camera_;                 // a copy: the test keeps no pointer to the image
  std::size_t width_ = 0, height_ = 0;
  std::vector<double> nearest_;  // the 3 × 3 minimum of the measured depths (inf where none)
  double spacing_factor_, relative_depth_;
};

/** The free space of an unorganised scan taken from one viewpoint (a terrestrial scanner, a frame
  * whose grid was lost): the measured points binned by direction from the viewpoint (azimuth and
  * elevation about a pole across the mean view direction, in bins of spacing / median range), each bin keeping its nearest range. A point lies in
  * seen-through space when it is nearer than the nearest measured range among its direction's 3 × 3
  * bins by more than max(spacing_factor × spacing, relative_range × that range). Directions with no
  * measurement are not judged. */
class ViewpointFreeSpaceTest {
public:
  ViewpointFreeSpaceTest(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& viewpoint, double spacing,
                         double spacing_factor = 2.0, double relative_range = 0.008);
  bool violates(const Eigen::Vector3d& p) const;

private:
  long long key(const Eigen::Vector3d& p) const;
  Eigen::Vector3d viewpoint_;
  Eigen::Matrix3d frame_ = Eigen::Matrix3d::Identity();  // rows: the mean view direction, two across it
  double bin_ = 0.0, spacing_, spacing_factor_, relative_range_;
  std::vector<std::pair<long long, double>> nearest_;  // sorted by key: the bin's nearest range
};

}  // namespace patchdict
}  // namespace pcl
