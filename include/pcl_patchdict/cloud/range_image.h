// A spinning LiDAR's organised grid as the range image it is: the beams fitted to its rows, the
// azimuth steps to its columns, the range-noise law (quantisation included) estimated from the scan.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** A measured point of a spinning LiDAR's frame: finite and not exactly at the sensor's origin —
  * (0, 0, 0) is how Ouster's and Velodyne's ROS drivers write "no return" in organised clouds. */
inline bool isReturn(const Eigen::Vector3d& p) { return p.allFinite() && !(p.x() == 0.0 && p.y() == 0.0 && p.z() == 0.0); }

/** \brief The rays of a spinning LiDAR (Ouster, Velodyne, Hesai): rows are beams at fixed
  * elevations, columns azimuth steps of the turn, all in the sensor's frame (z the spin axis).
  *
  * Pixel (column c, row b) looks along direction(b, c) = (cos e_b cos a, cos e_b sin a, sin e_b),
  * a = azimuth_start + c·azimuth_step + azimuth_offset[b], from its beam's origin
  * (beam_radius·cos a, beam_radius·sin a, beam_height): the beam origins of a spinning head lie on
  * a circle about the axis (15.8 mm and 36.2 mm on an Ouster OS1). A pixel's range is measured from
  * that origin along its direction. */
struct SpinningSensorModel {
  std::size_t width = 0, height = 0;   ///< columns (azimuth steps) and rows (beams)
  std::vector<double> elevation;       ///< per beam, radians, strictly monotonic over the rows
  std::vector<double> azimuth_offset;  ///< per beam, radians (a destaggered grid's residual offsets)
  double azimuth_start = 0.0, azimuth_step = 0.0;  ///< column 0's azimuth and the step (signed)
  double beam_radius = 0.0, beam_height = 0.0;
  bool wraps = false;   ///< the columns make a whole turn: column W−1 neighbours column 0
  bool valid = false;   ///< the grid was fitted and is a spinning sensor's
  /// Each row's points lie at one elevation, apart from the other rows': the rows are a spinning
  /// sensor's beams even when the grid cannot be used as one (rows out of order, columns that are
  /// no azimuth steps). Such a grid is refused rather than repaired as something else.
  bool rows_are_beams = false;
  std::string failure;  ///< why not, in one line, when !valid
  double rms_radians = 0.0;   ///< RMS angle between the points used and their pixels' rays
  std::size_t off_ray = 0;    ///< finite points farther than half a step from their pixel's ray

  /// Column c's azimuth on beam `row`; c may lie outside the grid or between columns (a window's
  /// offsets about a pixel).
  double azimuth(std::size_t row, double column) const
  {
    return azimuth_start + column * azimuth_step + azimuth_offset[row];
  }
  Eigen::Vector3d direction(std::size_t row, double column) const
  {
    const double a = azimuth(row, column), e = elevation[row];
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
  }
  Eigen::Vector3d rayOrigin(std::size_t row, double column) const
  {
    const double a = azimuth(row, column);
    return {beam_radius * std::cos(a), beam_radius * std::sin(a), beam_height};
  }
  Eigen::Vector3d pointAt(std::size_t row, double column, double range) const
  {
    return rayOrigin(row, column) + range * direction(row, column);
  }
  /** The smallest angle between neighbouring beams (radians). */
  double beamGap() const;
};

/** Every pixel's ray of a model: its direction and its beam's origin (row-major). */
struct SpinningRays {
  std::vector<Eigen::Vector3d> direction, origin;
};

/** The rays of a model, by angle addition over a table of the columns' and the beams' angles;
  * a stream's frames share them. */
std::shared_ptr<const SpinningRays> spinningRays(const SpinningSensorModel& model);

/** The measured ranges of an organised cloud on its sensor's rays. */
struct RangeImage {
  std::size_t width = 0, height = 0;
  SpinningSensorModel model;
  std::vector<double> range;   ///< along the pixel's ray from its beam origin; NaN where no measurement
  std::vector<char> valid;     ///< 1 where range is a measurement on the pixel's ray
  std::shared_ptr<const SpinningRays> rays;  ///< the model's rays (shared, not copied, with the image)
  std::size_t measured() const;
  const Eigen::Vector3d& direction(std::size_t i) const { return rays->direction[i]; }
  const Eigen::Vector3d& rayOrigin(std::size_t i) const { return rays->origin[i]; }
  /** The point at range r on pixel i's ray. */
  Eigen::Vector3d pointAt(std::size_t i, double r) const { return rays->origin[i] + r * rays->direction[i]; }
};

/** Fits a spinning sensor to an organised grid (points in the sensor's frame, NaN = no return).
  * Per beam, its points' elevation as seen from the beam-origin circle (one line z = t·h + c in
  * horizontal distance h, then the circle's radius and height from all beams' lines); per column,
  * the azimuth step (the median step between neighbours in a row) and per beam its offset (the
  * circular median). Not valid (failure says why) when fewer than 16 points are finite, the rows'
  * elevations are not strictly monotonic (rows that are not beams, or not in order), a beam's
  * points spread over more than a third of the gap to its neighbours, or more than 10 % of the
  * finite points lie over half a step off their pixel's ray (columns that are not azimuth steps). */
SpinningSensorModel fitSpinningSensor(const std::vector<Eigen::Vector3d>& points, std::size_t width,
                                      std::size_t height);

/** The range image of a cloud on a model (fitted, or given for a stream of frames). Points over half
  * a step off their pixel's ray, not in front of it, or at a range 1000 × off the frame's typical
  * one, are no measurements (counted in model.off_ray). Throws pcl::patchdict::Error when a given model does not fit: another width or
  * height, or more than 10 % of the finite points off their rays (a frame of another sensor). */
RangeImage makeRangeImage(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& model);
/** The same on the model's rays computed beforehand (spinningRays): a stream computes them once. */
RangeImage makeRangeImage(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& model,
                          const std::shared_ptr<const SpinningRays>& rays);

/** σ(ρ) = max(coefficient·ρ^exponent, quantum/√12): the noise of range along the ray. A pulsed or
  * phase-measuring LiDAR's noise grows slowly with range; its range is stored in steps (1 mm, or
  * 8 mm in Ouster's low-bandwidth profile), which is noise too. */
struct RangeNoiseModel {
  double coefficient = 0.0;
  double exponent = 0.0;
  bool exponent_fitted = false;  ///< false: the ranges span too little to fit it; 0 assumed
  double quantum = 0.0;          ///< the range step found in the data (0: none found)
  std::size_t samples = 0;       ///< planar 1 × 7 windows along the beams the estimate used
  double range_low = 0.0, range_high = 0.0;  ///< 5th and 95th percentiles of the sampled ranges
  double sigma(double range) const;
};

/** Estimates the range noise along the beams, where neighbours are closest: for every pixel (on a
  * stride) with at least 5 of its 6 neighbours ±3 columns along its beam measured within 5 % of its
  * range, the centre's range is predicted by a plane through them (on one beam, 1/ρ of a plane is
  * A·cos a + B·sin a + C in the azimuth a), and the residual over √(1 + leverage) is one sample.
  * The exponent is the log-log slope of six range bins' robust σ (1.4826 × the median |r|; clamped
  * to [0, 2]) when the 95th/5th range ratio is at least 2; the coefficient is the robust σ of r/ρ^p.
  * The quantum is the largest step q of 0.1, 0.2, 0.25, 0.5, 1, 2, 2.5, 4, 5, 8, 10, 16, 20, 32, 50
  * or 64 mm (ranges in metres) on which the ranges sit: the circular mean of exp(2πiρ/q) above 0.5. */
RangeNoiseModel estimateRangeNoise(const RangeImage& image, std::size_t stride = 2);

/** A field's values (intensity, reflectivity…) at filled pixels of a W × H grid: the inverse-distance
  * mean of the nearest measured pixel in each of the four grid directions (the columns wrapping when
  * `wraps`); pixels without a measured one in any direction keep theirs. */
void interpolateAtFilledPixels(std::vector<double>& values, const std::vector<char>& measured, std::size_t width,
                               std::size_t height, bool wraps, const std::vector<std::size_t>& filled);

/** A spinning sensor's free space: the smallest measured range among a pixel's 8 neighbours
  * (azimuth wrapping when the model wraps; beams do not; infinity where none is measured). A point
  * placed, or moved, on pixel i's ray nearer than that would be in space the beams crossed. */
std::vector<double> nearestMeasuredRange(const RangeImage& image);

/** The least range a point may take on a pixel whose neighbours' nearest measured range is
  * `nearest`: nearest − max(spacing_factor × nearest × |azimuth step|, relative_range × nearest)
  * (−∞ where nothing is measured around it). */
inline double freeSpaceBound(double nearest, double azimuth_step, double spacing_factor, double relative_range)
{
  if (!std::isfinite(nearest))
    return -std::numeric_limits<double>::infinity();
  return nearest - std::max(spacing_factor * nearest * std::abs(azimuth_step), relative_range * nearest);
}

/** The same space as seen from the sensor's origin, the single viewpoint that ray-casting tools
  * (occupancy maps, free-space checks) assume: near the sensor the beam origins' offset turns a
  * point's direction from the origin towards another beam's pixel. A point lies in that space when
  * it is nearer the origin than every measured point of the 3 × 3 pixels around the beam and column
  * its direction from the origin falls on, by more than max(spacing_factor × the pixel spacing
  * there, relative_range × that range) — as FreeSpaceTest judges a depth image. */
class OriginFreeSpace {
public:
  explicit OriginFreeSpace(const RangeImage& image, double spacing_factor = 2.0, double relative_range = 0.008);
  /** True when p (in the sensor's frame) lies in that space, judged at a pixel other than `own`
    * (its own pixel is judged by nearestMeasuredRange, strictly). */
  bool violates(const Eigen::Vector3d& p, std::size_t own) const;

private:
  const RangeImage& image_;
  std::vector<double> nearest_;  // 3 × 3 minimum of |point| over measured pixels
  bool descending_ = true;       // elevations fall with the row
  std::vector<double> tangent_;  // tan of each beam's elevation
  double spacing_factor_, relative_range_;
  double far_squared_ = 0.0;  // beyond this (squared) distance every point's direction is its own pixel's
};

}  // namespace patchdict
}  // namespace pcl
