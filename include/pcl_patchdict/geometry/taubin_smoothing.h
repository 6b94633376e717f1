// TaubinSmoother — Taubin's λ|μ low-pass filter (SIGGRAPH 1995) with inverse-distance weights
// (Fujiwara 1995) frozen at the input: a linear filter, one λ step and one μ step per iteration.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief x ← x + f·(Σ_j w_ij x_j / Σ_j w_ij − x) with f = λ, then f = μ, per iteration; w_ij =
  * 1/|x_i − x_j| of the mesh given to the constructor (frozen: noise does not re-weight later
  * steps). Boundary vertices are smoothed along the boundary only, so rims keep their place.
  * (Compared with Open3D's filter_smooth_taubin, re-weighted each step: figures in docs/.) */
class TaubinSmoother {
public:
  /** InverseDistance: w_ij = 1/|x_i − x_j| (the denoising base); Uniform: the plain mean of the
    * neighbours (the classic umbrella operator of CoarseMeshEstimation). */
  enum class Weights { InverseDistance, Uniform };

  /** Throws Error for face indices out of range or non-finite vertices. */
  explicit TaubinSmoother(const TriangleMesh& mesh, double lambda = 0.5, double mu = -0.53,
                          Weights weights = Weights::InverseDistance);

  /** One λ step and one μ step on `positions` (one per vertex of the constructor's mesh). */
  void iterate(std::vector<Eigen::Vector3d>& positions) const;

  /** One step x ← x + factor·(weighted mean of the neighbours − x); Laplacian smoothing is this
    * step with factor λ alone. */
  void step(std::vector<Eigen::Vector3d>& positions, double factor) const;

private:

  std::vector<std::int64_t> offsets_;      // CSR rows: neighbours of vertex v in [offsets_[v], offsets_[v + 1])
  std::vector<std::int32_t> neighbours_;
  std::vector<double> weights_;            // normalised per row; empty for uniform weights
  double lambda_, mu_;
};

}  // namespace patchdict
}  // namespace pcl
