// Least-squares bi-Laplacian interpolation of free vertices (Sorkine & Cohen-Or, "Least-squares
// meshes", SMI 2004, with the uniform Laplacian), optionally with soft point-to-plane constraints
// that couple the three coordinates: the linear core of the mesh repairs (patch_repairs.h).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

/** A soft constraint n·(x_v − p) = 0 on free vertex v (n unit), with weight w ≥ 0: the energy term
  * is w·(n·x_v − n·p)². It pulls x_v along n only; the tangential position stays the Laplacian's. */
struct PointToPlaneConstraint {
  std::int32_t vertex = -1;
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double weight = 0.0;
};

/** \brief Minimises Σ_i |(L x)_i|² + μ·Σ_c w_c (n_c·(x_{v_c} − p_c))² over the free vertices, the
  * others fixed, L the uniform Laplacian (x_i − mean of the 1-ring; rows of vertices without
  * neighbours are x_i itself). Only rows that involve a free vertex matter. Without constraints the
  * three coordinates are three independent solves of the same matrix; with them, one solve of
  * 3·|free| unknowns (SimplicialLDLT on the normal equations).
  *
  * `positions` holds every vertex: the free ones are overwritten with the solution, the fixed ones
  * are never written. `is_free` has one flag per vertex. Throws Error when the system is singular
  * (a connected part of the mesh with free vertices and no fixed one) or sizes disagree. */
class PatchConstrainedSolver {
public:
  /** Factorisation-independent set-up: connectivity and which vertices are free. */
  PatchConstrainedSolver(const TriangleMesh& mesh, const std::vector<bool>& is_free);

  /** Solves with the given constraints (none: the plain least-squares bi-Laplacian). */
  void solve(std::vector<Eigen::Vector3d>& positions, const std::vector<PointToPlaneConstraint>& constraints = {},
             double constraint_weight = 1.0) const;

  std::size_t numFree() const { return free_vertices_.size(); }
  const std::vector<std::int32_t>& freeVertices() const { return free_vertices_; }
  /** Index of a vertex among the free ones (−1 for fixed vertices). */
  std::int32_t freeIndex(std::int32_t vertex) const { return free_index_[static_cast<std::size_t>(vertex)]; }

private:
  std::vector<std::vector<std::int32_t>> rings_;
  std::vector<std::int32_t> free_vertices_;
  std::vector<std::int32_t> free_index_;
};

}  // namespace patchdict
}  // namespace pcl
