// Rotation (rows X, Y, Z) ↔ pcl::ReferenceFrame.
#include <pcl_patchdict/pcl/reference_frame.h>

namespace pcl {
namespace patchdict {

pcl::ReferenceFrame toReferenceFrame(const Eigen::Matrix3d& rows)
{
  pcl::ReferenceFrame frame;
  for (int k = 0; k < 3; ++k) {
    frame.x_axis[k] = static_cast<float>(rows(0, k));
    frame.y_axis[k] = static_cast<float>(rows(1, k));
    frame.z_axis[k] = static_cast<float>(rows(2, k));
  }
  return frame;
}

Eigen::Matrix3d fromReferenceFrame(const pcl::ReferenceFrame& frame)
{
  Eigen::Matrix3d rows;
  for (int k = 0; k < 3; ++k) {
    rows(0, k) = frame.x_axis[k];
    rows(1, k) = frame.y_axis[k];
    rows(2, k) = frame.z_axis[k];
  }
  return rows;
}

pcl::PointCloud<pcl::ReferenceFrame> toReferenceFrames(const std::vector<Eigen::Matrix3d>& frames)
{
  pcl::PointCloud<pcl::ReferenceFrame> cloud;
  cloud.reserve(frames.size());
  for (const Eigen::Matrix3d& rows : frames)
    cloud.push_back(toReferenceFrame(rows));  // push_back keeps width = size, height = 1
  return cloud;
}

std::vector<Eigen::Matrix3d> fromReferenceFrames(const pcl::PointCloud<pcl::ReferenceFrame>& frames)
{
  std::vector<Eigen::Matrix3d> rows;
  rows.reserve(frames.size());
  for (const pcl::ReferenceFrame& frame : frames)
    rows.push_back(fromReferenceFrame(frame));
  return rows;
}

}  // namespace patchdict
}  // namespace pcl
