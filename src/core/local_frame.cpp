#include <pcl_patchdict/core/local_frame.h>

#include <cmath>

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

bool patchContains(const Eigen::Vector3d& seed, const Eigen::Matrix3d& rotation, double radius,
                   const Eigen::Vector3d& p, const Eigen::Vector3d& normal, Eigen::Vector3d* local_out)
{
  const Eigen::Vector3d offset = p - seed;
  if (offset.norm() > radius)
    return false;
  const Eigen::Vector3d local = rotation * offset;
  const double half_side = radius / std::sqrt(2.0);  // patch side √2·r
  if (std::abs(local.x()) >= half_side || std::abs(local.y()) >= half_side)
    return false;
  if (rotation.row(2).dot(normal) < 0.0)
    return false;
  if (local_out)
    *local_out = local;
  return true;
}

}  // namespace patchdict
}  // namespace pcl
