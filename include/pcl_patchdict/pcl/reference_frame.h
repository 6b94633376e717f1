// Conversions between the core's frames (an Eigen::Matrix3d whose rows are a frame's X, Y, Z axes,
// core/local_frame.h) and pcl::ReferenceFrame, for PCL users: the core never sees the float type.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <vector>

namespace pcl {
namespace patchdict {

/** Rows X, Y, Z → pcl::ReferenceFrame (single precision: each entry rounded to nearest). */
pcl::ReferenceFrame toReferenceFrame(const Eigen::Matrix3d& rows);
/** pcl::ReferenceFrame → rows X, Y, Z (exact). */
Eigen::Matrix3d fromReferenceFrame(const pcl::ReferenceFrame& frame);

/** A list of frames (e.g. PatchLayout::frames) as a cloud of pcl::ReferenceFrame (width = count,
  * height 1). */
pcl::PointCloud<pcl::ReferenceFrame> toReferenceFrames(const std::vector<Eigen::Matrix3d>& frames);
/** A cloud of pcl::ReferenceFrame as the core's frames, e.g. for extractMeshHeightMaps. */
std::vector<Eigen::Matrix3d> fromReferenceFrames(const pcl::PointCloud<pcl::ReferenceFrame>& frames);

}  // namespace patchdict
}  // namespace pcl
