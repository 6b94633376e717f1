// Thin-plate spline height field: the function of (u, v) of least bending energy through (or, with
// smoothing, near) scattered heights — f(x) = a0 + a1·u + a2·v + Σ w_i φ(|x − x_i|), φ(r) = r² log r.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace pcl {
namespace patchdict {

/** \brief A 2D thin-plate spline (Duchon 1977; Bookstein, "Principal warps", IEEE PAMI 1989):
  * minimises Σ (z_i − f(x_i))² + λ·∫ (f_uu² + 2 f_uv² + f_vv²) up to constant factors — λ = 0
  * interpolates. Solves the (n + 3)² system [K + λ·I, P; Pᵀ, 0] once (dense, n up to a few
  * thousand), with K evaluated on the sites centred and scaled into the unit disc (so λ does not
  * depend on the units). */
class ThinPlateSpline {
public:
  /** Fits heights z at sites (u_i, v_i). Throws Error for fewer than 3 sites, sizes that differ,
    * non-finite values, λ < 0, or sites that are all collinear. */
  void fit(const std::vector<Eigen::Vector2d>& sites, const std::vector<double>& heights, double smoothing = 0.0);
  double operator()(const Eigen::Vector2d& x) const;
  /** ∂f/∂u, ∂f/∂v at x. */
  Eigen::Vector2d gradient(const Eigen::Vector2d& x) const;
  bool empty() const { return sites_.empty(); }

private:
  std::vector<Eigen::Vector2d> sites_;
  Eigen::VectorXd weights_;
  Eigen::Vector3d affine_ = Eigen::Vector3d::Zero();
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  double scale_ = 1.0;  // sites are centred and scaled to unit size for conditioning
};

}  // namespace patchdict
}  // namespace pcl
