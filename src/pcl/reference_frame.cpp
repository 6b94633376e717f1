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

}  // namespace patchdict
}  // namespace pcl
