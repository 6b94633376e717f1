// PointSearch — nearest-point queries over points kept in double: a FLANN kd-tree built once, in
// float (callers recompute exact distances in double). Private to the library.
#pragma once

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

inline pcl::PointXYZ toPointXYZ(const Eigen::Vector3d& p)
{
  return pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
}

/** A float search radius no smaller than `radius` for coordinates of order one (the unit cube):
  * the caller then tests the exact distance in double. */
inline float floatSearchRadius(double radius) { return static_cast<float>(radius * (1.0 + 1e-5) + 1e-7); }

/** The kd-tree of `points` (rounded to float), built once and searched from any thread. `sorted`:
  * radius results nearest first (FLANN's default), else in FLANN's own order. */
class PointSearch {
public:
  explicit PointSearch(const std::vector<Eigen::Vector3d>& points, bool sorted = true) : tree_(sorted)
  {
    pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
    cloud->resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      (*cloud)[i] = toPointXYZ(points[i]);
    tree_.setInputCloud(cloud);
  }
  /** The k nearest points of p (indices, squared float distances); how many were found. */
  int nearest(const Eigen::Vector3d& p, int k, std::vector<int>& found, std::vector<float>& squared) const
  {
    return tree_.nearestKSearch(toPointXYZ(p), k, found, squared);
  }
  /** The points within `radius` (a float radius, as given: see floatSearchRadius) of p. */
  int within(const Eigen::Vector3d& p, float radius, std::vector<int>& found, std::vector<float>& squared) const
  {
    return tree_.radiusSearch(toPointXYZ(p), radius, found, squared);
  }

private:
  pcl::KdTreeFLANN<pcl::PointXYZ> tree_;
};

/** Mean distance of (up to 20,000 evenly strided) points to their nearest other point; 0 when none
  * has a neighbour. */
inline double meanNearestSpacing(const std::vector<Eigen::Vector3d>& points)
{
  const PointSearch tree(points);
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 20000);
  double sum = 0.0;
  std::size_t count = 0;
  std::vector<int> near(2);
  std::vector<float> squared(2);
  for (std::size_t i = 0; i < points.size(); i += stride)
    if (tree.nearest(points[i], 2, near, squared) == 2) {
      sum += std::sqrt(static_cast<double>(squared[1]));
      ++count;
    }
  return count ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
