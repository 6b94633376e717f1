// Input hygiene for clouds: gross outliers (coordinates no sensor measured, such as a depth of 1e30
// written into a frame) set to NaN, and exact copies of a point found.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

/** Sets to NaN every finite point farther (on some axis) than `factor` × the robust extent from the
  * median of the finite points — the extent is the largest interquartile range of the three axes, at
  * least 1e-12 × the median's magnitude, so up to a quarter of the points may be wild — and returns
  * how many. A cloud of ordinary shape loses nothing: its points lie within a few extents of the
  * median. Deterministic. */
std::size_t removeGrossOutliers(std::vector<Eigen::Vector3d>& points, double factor = 1000.0);

/** For every point, the smallest index of a point at exactly its position (itself when it is the
  * first, or not finite): exact copies, found by sorting. */
std::vector<std::size_t> firstCopies(const std::vector<Eigen::Vector3d>& points);

}  // namespace patchdict
}  // namespace pcl
