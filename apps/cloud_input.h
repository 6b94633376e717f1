// Point-cloud inputs of the repair commands: which files are clouds, and reading one with every
// field, its organisation and its viewpoint (PCD), or positions and normals (face-less PLY).
#pragma once

#include <pcl/PCLPointCloud2.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** True for .pcd, and for a .ply whose header declares no faces (a vertex-only PLY). */
bool isCloudFile(const std::string& path);

struct CloudInput {
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud;  ///< organised as the file (NaN points kept); zero normals when absent
  pcl::PCLPointCloud2 blob;                      ///< PCD: every field, as read
  bool from_pcd = false;
  bool has_normals = false;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity();
  double scale = 1.0;  ///< largest side of the finite points' bounding box (the normalised unit)
  /// The cloud's positions are relative to this point (its bounding-box centre), so that float32
  /// keeps their precision even far from the origin (float64 PCDs of georeferenced scans).
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> positions;  ///< the positions as read, in double (NaN kept)
};

/** Reads a cloud file; Error (one line) when unreadable, empty, or without a finite point. */
CloudInput loadCloudInput(const std::string& path);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
