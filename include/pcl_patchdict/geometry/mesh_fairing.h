// Mesh fairing: moves chosen vertices so that L^(k+1) x = 0 there (L the cotangent Laplacian), all
// other vertices fixed — the smoothest surface through the fixed ones (Botsch et al., Polygon Mesh Processing, 2010, ch. 4).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

enum class FairingWeights {
  Cotangent,  ///< (cot α + cot β) / 2 over the mixed Voronoi area (Meyer et al. 2003): geometry-aware
  Uniform     ///< 1 over the valence: connectivity only (for free vertices whose positions mean nothing yet)
};

struct FairingOptions {
  /** k in L^(k+1) x = 0: 0 membrane (harmonic, C0), 1 thin plate (bi-Laplacian, C1, the default;
    * Liepa's and CGAL's choice), 2 minimum curvature variation (tri-Laplacian, C2). */
  int continuity = 1;
  FairingWeights weights = FairingWeights::Cotangent;
};

struct FairingReport {
  std::size_t free_vertices = 0;
  std::size_t fixed_vertices_used = 0;  ///< fixed vertices in the free vertices' (k+1)-rings
  bool solved = false;
};

/** \brief Solves L^(k+1) x = 0 at the free vertices with every other vertex fixed (the Dirichlet
  * problem of the k-harmonic equation) and writes the solution into mesh.vertices.
  *
  * Weights are computed once, from the current positions (also those of the free vertices: give
  * them a sensible first guess, or use Uniform weights). The system (one unknown per free vertex,
  * three right-hand sides) is the rows of L^(k+1) scaled by the vertex areas, W (D⁻¹W)^k, which is
  * symmetric: solved by Eigen's SimplicialLDLT, with SparseLU (COLAMD) as fallback. Free vertices
  * with no path of faces to a fixed vertex make the system singular.
  * Returns false and leaves the mesh unchanged when the solve fails or is not finite; throws Error
  * for an index out of range or continuity outside 0..2. Duplicate indices are ignored. */
bool fairVertices(TriangleMesh& mesh, const std::vector<std::int32_t>& free_vertices,
                  const FairingOptions& options = {}, FairingReport* report = nullptr);

}  // namespace patchdict
}  // namespace pcl
