// Conversions between a rotation whose rows are a frame's X, Y, Z axes and pcl::ReferenceFrame.
#pragma once

#include <pcl/point_types.h>

#include <Eigen/Core>

namespace pcl {
namespace patchdict {

/** Rows X, Y, Z → pcl::ReferenceFrame (single precision). */
pcl::ReferenceFrame toReferenceFrame(const Eigen::Matrix3d& rows);
/** pcl::ReferenceFrame → rows X, Y, Z. */
Eigen::Matrix3d fromReferenceFrame(const pcl::ReferenceFrame& frame);

}  // namespace patchdict
}  // namespace pcl
