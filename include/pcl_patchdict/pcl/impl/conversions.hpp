// Templated point-cloud conversions of TriangleMesh (toPointCloud, fromPointCloud).
#pragma once

#include <cmath>
#include <type_traits>

#include <pcl/point_types.h>

namespace pcl {
namespace patchdict {

template <typename PointT>
void toPointCloud(const TriangleMesh& mesh, pcl::PointCloud<PointT>& cloud)
{
  cloud.clear();
  cloud.resize(mesh.vertices.size());
  const bool with_normals = mesh.hasNormals();
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    PointT& p = cloud[i];
    p.x = static_cast<float>(mesh.vertices[i].x());
    p.y = static_cast<float>(mesh.vertices[i].y());
    p.z = static_cast<float>(mesh.vertices[i].z());
    if constexpr (pcl::traits::has_normal_v<PointT>) {
      if (with_normals) {
        p.normal_x = static_cast<float>(mesh.normals[i].x());
        p.normal_y = static_cast<float>(mesh.normals[i].y());
        p.normal_z = static_cast<float>(mesh.normals[i].z());
      } else {
        p.normal_x = p.normal_y = p.normal_z = 0.f;
      }
    }
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
}

template <typename PointT>
void fromPointCloud(const pcl::PointCloud<PointT>& cloud, TriangleMesh& mesh,
                    std::vector<int>* index_map)
{
  mesh = TriangleMesh();
  if (index_map)
    index_map->clear();
  bool all_normals = pcl::traits::has_normal_v<PointT>;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointT& p = cloud[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      continue;
    mesh.vertices.emplace_back(p.x, p.y, p.z);
    if constexpr (pcl::traits::has_normal_v<PointT>) {
      Eigen::Vector3d n(p.normal_x, p.normal_y, p.normal_z);
      if (!n.allFinite())
        all_normals = false;
      mesh.normals.push_back(n);
    }
    if (index_map)
      index_map->push_back(static_cast<int>(i));
  }
  if (!all_normals)
    mesh.normals.clear();
}

}  // namespace patchdict
}  // namespace pcl
