// Biharmonic implicit surface: f(x) = Σ w_i |x − c_i| + a·x + b through oriented points, f = 0 on
// them and ±ε at ε along their normals; its zero set is the smoothest surface through them in 3D.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace pcl {
namespace patchdict {

/** \brief The 3D radial-basis implicit of Carr et al., "Reconstruction and representation of 3D
  * objects with radial basis functions" (SIGGRAPH 2001): φ(r) = r, the fundamental solution of the
  * biharmonic operator in 3D, so that f minimises ∫ |∇²f|² among the functions meeting the
  * constraints (Duchon). Off-surface constraints f(p ± ε n) = ±ε fix the sign, so f grows along
  * the normals. Unlike a height field over a plane, its zero set may fold, bend back or have
  * several sheets: a hole through the folds of a scan is filled as one surface.
  * The (3n + 4)² system is solved once, dense (n up to a few hundred points). */
class BiharmonicImplicit {
public:
  /** Fits f through the points with their normals; ε > 0, in the points' units (halved, up to 3
    * times, where an offset point would be nearer another point than its own). Throws Error for
    * fewer than 4 points, sizes that differ, non-finite values, zero normals, ε ≤ 0, or a singular
    * system (duplicate points); a failed fit leaves the previous one in place. */
  void fit(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& normals, double epsilon);
  double operator()(const Eigen::Vector3d& x) const;
  Eigen::Vector3d gradient(const Eigen::Vector3d& x) const;
  /** f(x), with ∇f(x) in `gradient` (one pass over the centres). */
  double valueAndGradient(const Eigen::Vector3d& x, Eigen::Vector3d& gradient) const;
  /** Newton steps along ∇f from x towards f = 0: true with the foot in x when |f| ≤ tolerance
    * within `iterations`, false (x unspecified) otherwise. */
  bool project(Eigen::Vector3d& x, double tolerance, int iterations = 12) const;
  bool empty() const { return centres_.empty(); }

private:
  std::vector<Eigen::Vector3d> centres_;  // centred and scaled into the unit ball
  Eigen::VectorXd weights_;
  Eigen::Vector4d affine_ = Eigen::Vector4d::Zero();  // b, a_x, a_y, a_z
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double scale_ = 1.0;
};

}  // namespace patchdict
}  // namespace pcl
