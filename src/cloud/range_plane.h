// Private: a plane seen from a ray origin is linear in the ray direction, 1/ρ = w·u (for a plane
// n·x = d through rays from one point, 1/ρ = n·u / d). Fitted in a basis about a centre ray
// (u·u_c, u·e1, u·e2), so that the normal equations stay well conditioned over a few pixels.
#pragma once

#include <Eigen/Core>

#include <cmath>

namespace pcl {
namespace patchdict {
namespace detail {

/** The basis about a centre ray u_c: coordinates (u·u_c, u·e1 / s, u·e2 / s), s an angle step. */
struct RayBasis {
  RayBasis(const Eigen::Vector3d& centre, double angle_scale) : u(centre), inverse_scale(1.0 / angle_scale)
  {
    // e1 = u × z (horizontal): a turn about the spin axis turns the basis with the ray. Rays within
    // 2.6° of the axis (no spinning LiDAR's) take x instead.
    const Eigen::Vector3d helper = std::abs(u.z()) < 0.999 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
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

/** Weighted least squares of 1/ρ over basis coordinates; 1/ρ at the centre ray is w(0). The 3 × 3
  * normal equations are accumulated in six scalars and solved by the adjugate: this runs for every
  * pixel of a frame, twice. */
struct InverseRangePlane {
  double a00 = 0.0, a01 = 0.0, a02 = 0.0, a11 = 0.0, a12 = 0.0, a22 = 0.0;
  double b0 = 0.0, b1 = 0.0, b2 = 0.0;
  double weight = 0.0;
  void add(const Eigen::Vector3d& x, double inverse_range, double w)
  {
    const double wx0 = w * x(0), wx1 = w * x(1), wx2 = w * x(2);
    a00 += wx0 * x(0);
    a01 += wx0 * x(1);
    a02 += wx0 * x(2);
    a11 += wx1 * x(1);
    a12 += wx1 * x(2);
    a22 += wx2 * x(2);
    b0 += wx0 * inverse_range;
    b1 += wx1 * inverse_range;
    b2 += wx2 * inverse_range;
    weight += w;
  }
  Eigen::Matrix3d normalMatrix() const
  {
    Eigen::Matrix3d A;
    A << a00, a01, a02, a01, a11, a12, a02, a12, a22;
    return A;
  }
  /** False when the fit is degenerate (too few or collinear rays: the determinant below 1e-12 of the
    * cube of the trace's third). */
  bool solve(Eigen::Vector3d& w) const
  {
    const double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22, c02 = a01 * a12 - a02 * a11;
    const double det = a00 * c00 + a01 * c01 + a02 * c02;
    const double scale = (a00 + a11 + a22) / 3.0;
    if (!(det > 1e-12 * scale * scale * scale))
      return false;
    const double c11 = a00 * a22 - a02 * a02, c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
    const Eigen::Vector3d solution(c00 * b0 + c01 * b1 + c02 * b2, c01 * b0 + c11 * b1 + c12 * b2,
                                   c02 * b0 + c12 * b1 + c22 * b2);
    if (!solution.allFinite())
      return false;
    w = solution / det;
    return true;
  }
  /** (A⁻¹)₀₀: the leverage of the centre's prediction (x₀ = (1, 0, 0)). */
  double centreLeverage() const
  {
    const double c00 = a11 * a22 - a12 * a12;
    const double det = a00 * c00 + a01 * (a02 * a12 - a01 * a22) + a02 * (a01 * a12 - a02 * a11);
    return c00 / det;
  }
};

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
