// PointCells — a cloud bucketed in cubic cells (a "cell list"): the points near a query are the
// points of the cells its box meets, read in one fixed order, with no tree and no sort per query.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

class PointCells {
public:
  /** Buckets `points` (finite) in cells of side ≥ `cell` (larger when the box would need more than
    * about 8 cells a point). Within a cell the points keep their index order. */
  PointCells(const std::vector<Eigen::Vector3d>& points, double cell);

  /** Calls visit(position, index) for every point of the cells that may hold a point within r of
    * centre (in each row of cells along x, those the ball's chord over the row can reach), in the
    * cells' order (z, y, x) and index order within a cell: the same order whatever the thread or
    * the caller. Points outside the ball are the caller's to skip. */
  template <typename Visit>
  void forEachNear(const Eigen::Vector3d& centre, double r, Visit&& visit) const
  {
    const int y0 = clampCell((centre[1] - r - origin_[1]) / cell_, 1);
    const int y1 = clampCell((centre[1] + r - origin_[1]) / cell_, 1);
    const int z0 = clampCell((centre[2] - r - origin_[2]) / cell_, 2);
    const int z1 = clampCell((centre[2] + r - origin_[2]) / cell_, 2);
    const double r2 = r * r;
    for (int z = z0; z <= z1; ++z) {
      const double dz = gap(centre[2], z, 2);
      for (int y = y0; y <= y1; ++y) {
        const double dy = gap(centre[1], y, 1);
        const double rest = r2 - dz * dz - dy * dy;
        if (rest < 0.0)
          continue;
        const double chord = std::sqrt(rest);
        const int x0 = clampCell((centre[0] - chord - origin_[0]) / cell_, 0);
        const int x1 = clampCell((centre[0] + chord - origin_[0]) / cell_, 0);
        // The x-run of cells is contiguous: one range of points.
        const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + static_cast<std::size_t>(y)) * dims_[0];
        const std::uint32_t begin = start_[row + static_cast<std::size_t>(x0)];
        const std::uint32_t end = start_[row + static_cast<std::size_t>(x1) + 1];
        for (std::uint32_t i = begin; i < end; ++i)
          visit(sorted_[i], index_[i]);
      }
    }
  }

private:
  /** Distance along `axis` from c to cell k's slab (0 inside it). */
  double gap(double c, int k, int axis) const
  {
    const double lo = origin_[axis] + k * cell_, hi = lo + cell_;
    return c < lo ? lo - c : (c > hi ? c - hi : 0.0);
  }

  int clampCell(double coordinate, int axis) const
  {
    if (!(coordinate > 0.0))
      return 0;
    const double last = static_cast<double>(dims_[axis] - 1);
    return coordinate >= last ? dims_[axis] - 1 : static_cast<int>(coordinate);
  }

  Eigen::Vector3d origin_;
  double cell_ = 1.0;
  int dims_[3] = {1, 1, 1};
  std::vector<std::uint32_t> start_;     ///< per cell (x fastest), its first point in sorted_; one more at the end
  std::vector<Eigen::Vector3d> sorted_;  ///< the points in cell order
  std::vector<std::uint32_t> index_;     ///< their indices in the input
};

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
