// Point-cloud inputs of the repair commands: which files are clouds, and reading one with every
// field, its organisation and its viewpoint (PCD), or positions and normals (face-less PLY).
#pragma once

#include <pcl_patchdict/pcl/conversions.h>  // readPointField
#include <pcl/PCLPointCloud2.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Geometry>

#include <set>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

/** True for .pcd, and for a .ply whose header declares no faces (a vertex-only PLY). */
bool isCloudFile(const std::string& path);

/** A field of one float32 or float64 value, or nullptr. */
const pcl::PCLPointField* findScalarField(const pcl::PCLPointCloud2& blob, const char* name);
/** An integer field of one value (INT8 … UINT32; Velodyne and Ouster write `ring` as uint16), or
  * nullptr. Either field's value in point i: readPointField (pcl/conversions.h). */
const pcl::PCLPointField* findIntegerField(const pcl::PCLPointCloud2& blob, const char* name);
/** A float field's value written into point i (float32 fields round). */
void writeScalar(pcl::PCLPointCloud2& blob, std::size_t point, const pcl::PCLPointField& field, double value);

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
  /// Finite points no sensor measured (removeGrossOutliers: e.g. a depth of 1e30): NaN in `cloud`,
  /// never written out.
  std::size_t gross_outliers = 0;
};

/** Reads a cloud file; Error (one line) when unreadable, empty, or without a finite point. */
CloudInput loadCloudInput(const std::string& path);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
