// Eigen points ↔ pcl::PointXYZ for the library's kd-tree queries (FLANN works in float; callers
// recompute exact distances in double). Private to the library.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

inline pcl::PointXYZ toPointXYZ(const Eigen::Vector3d& p)
{
  return pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
}

inline pcl::PointCloud<pcl::PointXYZ>::Ptr toCloudXYZ(const std::vector<Eigen::Vector3d>& points)
{
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    (*cloud)[i] = toPointXYZ(points[i]);
  return cloud;
}

/** A float search radius no smaller than `radius` for coordinates of order one (the unit cube):
  * the caller then tests the exact distance in double. */
inline float floatSearchRadius(double radius) { return static_cast<float>(radius * (1.0 + 1e-5) + 1e-7); }

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
