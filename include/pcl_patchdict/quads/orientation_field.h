// Multi-resolution vertex graph and extrinsic 4-RoSy orientation field — the first stage of
// field-aligned quad remeshing after Jakob, Tarini, Panozzo & Sorkine-Hornung 2015 (§2.2, §2.4; docs/design.md, "Field-aligned quads").
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace pcl {
namespace patchdict {

/** One level of the hierarchy (Jakob et al. 2015, §5 "multiresolution hierarchy"): a weighted vertex
  * graph with positions, unit normals and dual areas. Adjacency is stored compressed (CSR): the
  * neighbours of vertex i are adjacency[adjacency_offsets[i] .. adjacency_offsets[i+1]). */
struct FieldLevel {
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> normals;  ///< unit; zero for a vertex no non-degenerate face uses
  std::vector<double> areas;             ///< dual (barycentric) areas; summed when vertices merge

  std::vector<std::int32_t> adjacency_offsets;  ///< size numVertices() + 1
  std::vector<std::int32_t> adjacency;          ///< neighbour indices, sorted per vertex
  std::vector<double> adjacency_weights;        ///< 1 per mesh edge at level 0; summed when merged

  /** Greedy graph colouring: vertices of one phase share no edge, so a phase can be smoothed in
    * parallel with Gauss–Seidel semantics. Every vertex is in exactly one phase. */
  std::vector<std::vector<std::int32_t>> phases;

  /** Children on the next finer level (level − 1), the second −1 when the vertex was copied
    * unmatched. Empty on level 0. */
  std::vector<std::array<std::int32_t, 2>> children;
  /** Parent on the next coarser level (level + 1). Empty on the coarsest level. */
  std::vector<std::int32_t> parents;

  std::size_t numVertices() const { return positions.size(); }
};

/** Levels from fine (0 = the mesh vertices) to coarse (back()). */
struct FieldHierarchy {
  std::vector<FieldLevel> levels;
  static constexpr int kMaxLevels = 25;  ///< MAX_DEPTH of the reference implementation

  std::size_t numLevels() const { return levels.size(); }
};

/** \brief Builds the hierarchy (Jakob et al. 2015 §5).
  * Level 0: mesh vertices, angle-weighted normals, one third of the incident face areas, weight 1
  * per edge. Each coarser level greedily matches edges in descending order of
  * (n_i·n_k)·max(A_i/A_k, A_k/A_i) (stable sort, ties by edge index, hence deterministic).
  * Coarsening stops at one vertex, at kMaxLevels levels, or when no edge is left to collapse
  * (a mesh with several components ends with one vertex per component).
  * Throws pcl::patchdict::Error for a mesh without faces or with an out-of-range face index. */
FieldHierarchy buildFieldHierarchy(const TriangleMesh& mesh);

struct OrientationFieldParameters {
  std::uint64_t seed = 0;        ///< seeds the random tangents on the coarsest level
  int iterations_per_level = 6;  ///< Gauss–Seidel sweeps per level ("levelIterations")
  int num_threads = 0;           ///< 0: OpenMP's default; the result does not depend on it
};

/** \brief compat_orientation_extrinsic_4 (Jakob et al. 2015 §4, extrinsic variant): among the
  * representatives {q0, n0×q0} and {q1, n1×q1} picks the pair (a, b) with the largest |a·b| and
  * returns (a, b·sign(a·b)). The vectors are compared directly in 3D (no parallel transport). */
std::pair<Eigen::Vector3d, Eigen::Vector3d> compatOrientationExtrinsic4(const Eigen::Vector3d& q0,
                                                                        const Eigen::Vector3d& n0,
                                                                        const Eigen::Vector3d& q1,
                                                                        const Eigen::Vector3d& n1);

/** \brief The integer form of the same match: which rotation k ∈ {0,1,2,3} of q1 about n1
  * (q1, n1×q1, −q1, −n1×q1) best matches q0, i.e. rot^k(q1) ≈ q0 up to the rotation chosen for q0. */
int compatOrientationExtrinsicIndex4(const Eigen::Vector3d& q0, const Eigen::Vector3d& n0,
                                     const Eigen::Vector3d& q1, const Eigen::Vector3d& n1);

/** \brief One unit tangent per vertex at a uniformly random angle in the tangent frame of its
  * normal (the initialisation of the reference implementation); deterministic for a seed.
  * Vertices with a zero normal get a random unit vector in the xy plane. */
std::vector<Eigen::Vector3d> randomTangentField(const std::vector<Eigen::Vector3d>& normals, std::uint64_t seed);

/** \brief Smooth extrinsic 4-RoSy field by hierarchical Gauss–Seidel (Jakob et al. 2015 §4–5):
  * random tangents on the coarsest level, iterations_per_level sweeps per level (phases in
  * sequence, vertices of a phase in parallel), prolongation to the children by projection onto
  * their tangent planes. Returns one unit tangent per level-0 vertex, orthogonal to its normal
  * (for a vertex with zero normal, the tangent is whatever the prolongation delivered). */
std::vector<Eigen::Vector3d> computeOrientationField(const FieldHierarchy& hierarchy,
                                                     const OrientationFieldParameters& parameters = {});

/** \brief Smoothness energy Σ over mesh edges of (1 − |a·b|) with (a, b) from
  * compatOrientationExtrinsic4: 0 for a field that is parallel in 3D across every edge. */
double orientationFieldEnergy(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& normals,
                              const std::vector<Eigen::Vector3d>& field);

/** \brief Per face, the sum mod 4 of the match indices along its edges (0→1, 1→2, 2→0): 0 regular,
  * 1 a singularity of index +1/4, 3 one of index −1/4 (for counter-clockwise faces seen from the
  * normal side), 2 a double singularity (rare; only on very coarse or very noisy fields). */
std::vector<int> computeOrientationSingularityIndices(const TriangleMesh& mesh,
                                                      const std::vector<Eigen::Vector3d>& normals,
                                                      const std::vector<Eigen::Vector3d>& field);

/** \brief Number of faces whose index sum is 1 or 3 (compute_orientation_singularities of the
  * reference implementation); optionally the list of those faces in increasing order. */
int countOrientationSingularities(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& normals,
                                  const std::vector<Eigen::Vector3d>& field,
                                  std::vector<int>* singular_faces = nullptr);

}  // namespace patchdict
}  // namespace pcl
