// PointCells: a counting sort of the points by cell (stable, so index order within a cell).
#include "patches/point_cells.h"

#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {
namespace detail {

PointCells::PointCells(const std::vector<Eigen::Vector3d>& points, double cell)
{
  if (points.empty() || points.size() >= std::numeric_limits<std::uint32_t>::max())
    throw Error("point cells: between 1 and 2^32 − 2 points are needed");
  if (!(cell > 0.0) || !std::isfinite(cell))
    throw Error("point cells: the cell side must be positive and finite");
  Eigen::Vector3d low = points.front(), high = points.front();
  for (const auto& p : points) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const Eigen::Vector3d extent = high - low;
  // At most about 8 cells a point (and at least 2^16 allowed): a sparse cloud in a large box gets
  // larger cells, not gigabytes of empty ones.
  const double budget = std::max(65536.0, 8.0 * static_cast<double>(points.size()));
  auto cells = [&](double side) {
    double total = 1.0;
    for (int a = 0; a < 3; ++a)
      total *= std::floor(extent[a] / side) + 1.0;
    return total;
  };
  while (cells(cell) > budget)
    cell *= 1.25;
  cell_ = cell;
  origin_ = low;
  for (int a = 0; a < 3; ++a)
    dims_[a] = static_cast<int>(std::floor(extent[a] / cell_)) + 1;
  const std::size_t total = static_cast<std::size_t>(dims_[0]) * dims_[1] * dims_[2];
  std::vector<std::size_t> cell_of(points.size());
  start_.assign(total + 1, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    int c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::min(dims_[a] - 1, static_cast<int>((points[i][a] - origin_[a]) / cell_));
    cell_of[i] = (static_cast<std::size_t>(c[2]) * dims_[1] + static_cast<std::size_t>(c[1])) * dims_[0] +
                 static_cast<std::size_t>(c[0]);
    ++start_[cell_of[i] + 1];
  }
  for (std::size_t k = 0; k < total; ++k)
    start_[k + 1] += start_[k];
  std::vector<std::uint32_t> next(start_.begin(), start_.end() - 1);
  sorted_.resize(points.size());
  index_.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::uint32_t at = next[cell_of[i]]++;
    sorted_[at] = points[i];
    index_[at] = static_cast<std::uint32_t>(i);
  }
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
