// QuadRemesher — field-aligned quad-dominant remeshing of a (coarse) triangle mesh after Jakob,
// Tarini, Panozzo & Sorkine-Hornung, "Instant Field-Aligned Meshes" (SIGGRAPH Asia 2015).
#pragma once

#include <pcl_patchdict/quads/orientation_field.h>
#include <pcl_patchdict/quads/quad_mesh.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Field-aligned quad remeshing (the paper's section 3.3, after Jakob et al. 2015).
  *
  * Stages: long input edges split until every edge is at most L/2 (the lattice needs several
  * vertices per quad side); multi-resolution hierarchy; extrinsic 4-RoSy orientation field;
  * extrinsic 4-PoSy position field with spacing L; extraction (extractQuadMesh). Vertices of the
  * result lie on the input surface. Deterministic for a given seed, whatever the thread count. */
class QuadRemesher {
public:
  using Ptr = std::shared_ptr<QuadRemesher>;
  using ConstPtr = std::shared_ptr<const QuadRemesher>;

  struct Report {
    std::size_t input_faces = 0, refined_faces = 0;  ///< before and after splitting long edges
    std::size_t hierarchy_levels = 0;
    int orientation_singularities = 0;  ///< faces of the refined mesh with index ±1/4
    double position_energy = 0.0;       ///< positionFieldEnergy / number of edges
    double seconds_refine = 0.0, seconds_hierarchy = 0.0, seconds_orientation = 0.0, seconds_position = 0.0,
           seconds_extraction = 0.0;
  };

  /** The mesh to remesh, shared (kept alive until it is replaced). */
  void setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh) { input_ = mesh; }
  /** Target edge length L (in the input's units). */
  void setQuadLength(double length) { quad_length_ = length; }
  double getQuadLength() const { return quad_length_; }
  void setSeed(std::uint64_t seed) { seed_ = seed; }
  void setIterationsPerLevel(int iterations) { iterations_ = iterations; }
  void setNumberOfThreads(int threads) { threads_ = threads; }

  /** Throws Error for a missing or face-less input, non-finite coordinates, an L that is not
    * positive, or an L so small against the input that the refined mesh would exceed
    * max_refined_faces (20 million). An L larger than the shape gives a tiny or empty mesh:
    * the result then has no faces, which the caller can report. */
  void process(QuadMesh& out, Report* report = nullptr) const;

  static constexpr std::size_t max_refined_faces = 20000000;

private:
  std::shared_ptr<const TriangleMesh> input_;
  double quad_length_ = 0.03;
  std::uint64_t seed_ = 0;
  int iterations_ = 6;
  int threads_ = 0;
};

/** \brief Splits every edge longer than max_length at its midpoint (longest first, rounds until
  * none is left); vertices and faces are appended, existing vertices keep their indices. */
TriangleMesh splitLongEdges(const TriangleMesh& mesh, double max_length, std::size_t max_faces = 20000000);

/** \brief Extraction of the quad-dominant mesh from the two fields (Jakob et al. 2015 §6;
  * Jakob et al. 2015 §6): mesh edges whose ends round to the same lattice point collapse (union-find,
  * lowest error first), edges between lattice neighbours become output edges, dangling vertices
  * are pruned, neighbours are sorted by angle about each output vertex, faces are walked in the
  * resulting rotation system, faces of 5–8 sides are split into quads (and a triangle when odd),
  * larger ones (open boundaries, holes) are dropped. Output vertices are the weighted means of
  * their cluster's origins, projected onto `mesh`. `mesh` is the mesh the hierarchy was built on. */
void extractQuadMesh(const TriangleMesh& mesh, const FieldLevel& level, const std::vector<Eigen::Vector3d>& orientation,
                     const std::vector<Eigen::Vector3d>& origins, double scale, QuadMesh& out);

}  // namespace patchdict
}  // namespace pcl
