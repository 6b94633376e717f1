// Small helpers shared by the orientation and position fields (private to the library).
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <random>

namespace pcl {
namespace patchdict {
namespace detail {

/** Orthonormal tangent frame (e1, e2) of a unit normal; any frame works, it only has to be a
  * deterministic function of n so that random initialisations are reproducible. */
inline void tangentFrame(const Eigen::Vector3d& n, Eigen::Vector3d& e1, Eigen::Vector3d& e2)
{
  // Drop the component with the larger magnitude of x/y to avoid a near-zero cross product.
  if (std::abs(n.x()) > std::abs(n.y()))
    e1 = Eigen::Vector3d(-n.z(), 0.0, n.x()) / std::sqrt(n.x() * n.x() + n.z() * n.z());
  else
    e1 = Eigen::Vector3d(0.0, n.z(), -n.y()) / std::sqrt(n.y() * n.y() + n.z() * n.z());
  e2 = n.cross(e1);
}

/** Uniform number in [0, 1) from 53 random bits: portable, unlike std::uniform_real_distribution
  * whose output differs between standard libraries. */
inline double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

/** Any unit tangent of n (used when a projection degenerates, e.g. a parent tangent along n). */
inline Eigen::Vector3d anyTangent(const Eigen::Vector3d& n)
{
  if (n.squaredNorm() == 0.0)
    return Eigen::Vector3d::UnitX();
  Eigen::Vector3d e1, e2;
  tangentFrame(n, e1, e2);
  return e1;
}

/** Projects q onto the tangent plane of n and normalises; falls back to any tangent. */
inline Eigen::Vector3d projectToTangent(const Eigen::Vector3d& q, const Eigen::Vector3d& n)
{
  Eigen::Vector3d t = q - n * n.dot(q);
  const double length = t.norm();
  if (length > 1e-12)
    return t / length;
  return anyTangent(n);
}

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
