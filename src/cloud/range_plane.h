// Private: a plane seen from a ray origin is linear in the ray direction, 1/ρ = w·u (for a plane
// n·x = d through rays from one point, 1/ρ = n·u / d). Fitted in a basis about a centre ray
// (u·u_c, u·e1, u·e2), so that the normal equations stay well conditioned over a few pixels.
#pragma once

#include <Eigen/Dense>

#include <cmath>

namespace pcl {
namespace patchdict {
namespace detail {

/** The basis about a centre ray u_c: coordinates (u·u_c, u·e1 / s, u·e2 / s), s an angle step. */
struct RayBasis {
  RayBasis(const Eigen::Vector3d& centre, double angle_scale) : u(centre), inverse_scale(1.0 / angle_scale)
  {
    const Eigen::Vector3d helper = std::abs(u.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
    e1 = u.cross(helper).normalized();
    e2 = u.cross(e1);
  }
  Eigen::Vector3d coordinates(const Eigen::Vector3d& direction) const
  {
    return {direction.dot(u), inverse_scale * direction.dot(e1), inverse_scale * direction.dot(e2)};
  }
  Eigen::Vector3d u, e1, e2;
  double inverse_scale;  ///< 1 / the angle of a pixel step: coordinates of order 1
};

/** Weighted least squares of 1/ρ over basis coordinates; 1/ρ at the centre ray is w(0). */
struct InverseRangePlane {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double weight = 0.0;
  void add(const Eigen::Vector3d& x, double inverse_range, double w)
  {
    A.selfadjointView<Eigen::Lower>().rankUpdate(x, w);
    b += w * inverse_range * x;
    weight += w;
  }
  /** False when the fit is degenerate (too few or collinear rays). */
  bool solve(Eigen::Vector3d& w) const
  {
    const Eigen::Matrix3d full = A.selfadjointView<Eigen::Lower>();
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(full);
    if (ldlt.info() != Eigen::Success || !(std::abs(ldlt.vectorD().minCoeff()) > 1e-14 * full.trace()))
      return false;
    const Eigen::Vector3d solution = ldlt.solve(b);
    if (!solution.allFinite())
      return false;
    w = solution;
    return true;
  }
};

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
