// Seeded damage for the demo and the benchmarks, on the evaluation protocol (docs/design.md): holes punched at
// well-separated centres, vertices dropped at random, Gaussian noise along the normals.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

/** A mesh with holes, and where its vertices came from. */
struct HoledMesh {
  TriangleMesh mesh;                        ///< the holed mesh (unreferenced vertices dropped)
  std::vector<std::int32_t> original_index; ///< per vertex of `mesh`, its index in the input
  std::vector<std::int32_t> removed;        ///< input vertices a face used that `mesh` no longer has
  std::vector<Eigen::Vector3d> centres;
};

/** \brief Removes every face with a vertex within `radius` of one of `count` centres: vertices drawn
  * at random (seeded), each at least 4 × radius from the others and 2 × radius from the mesh's
  * boundary (fewer centres when the surface has no room). Unreferenced vertices are dropped; the kept ones keep their order. Throws Error
  * for a mesh without faces, count < 1 or radius ≤ 0. */
HoledMesh punchHoles(const TriangleMesh& mesh, int count, double radius, std::uint64_t seed);

/** The protocol's two hole scores (docs/design.md), in the truth's units. */
struct HoleFillScore {
  double removed_to_output = 0.0;  ///< mean distance of the removed true vertices to the filled surface
  double new_to_truth = 0.0;       ///< mean distance of the fill's new vertices to the true surface
};

/** \brief Scores `filled` — the holed mesh's vertices first, then new ones (HoleFilling's order) —
  * against the mesh the holes were punched in. */
HoleFillScore scoreHoleFill(const TriangleMesh& truth, const HoledMesh& holed, const TriangleMesh& filled);

/** \brief round(fraction × V) distinct vertex indices, increasing, drawn at random (seeded) among the
  * vertices used by a face. Throws Error unless 0 < fraction < 1. */
std::vector<int> pickMissingVertices(const TriangleMesh& mesh, double fraction, std::uint64_t seed);

/** \brief The mesh with each vertex moved by N(0, σ²) along its (angle-weighted) vertex normal, seeded; σ = 0
  * returns the mesh, a negative or non-finite σ is an Error. */
TriangleMesh addNormalNoise(const TriangleMesh& mesh, double sigma, std::uint64_t seed);

}  // namespace patchdict
}  // namespace pcl
