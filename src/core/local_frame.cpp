#include <pcl_patchdict/core/local_frame.h>

namespace pcl {
namespace patchdict {

Eigen::Matrix3d roundToSinglePrecision(const Eigen::Matrix3d& frame)
{
  // static_cast<float> rounds to nearest, as toReferenceFrame's casts do; float → double is exact.
  Eigen::Matrix3d rounded;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      rounded(r, k) = static_cast<double>(static_cast<float>(frame(r, k)));
  return rounded;
}

}  // namespace patchdict
}  // namespace pcl
