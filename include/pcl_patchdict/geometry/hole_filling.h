// HoleFilling — closes the holes of a triangle mesh by Liepa's triangulate–refine–fair (P. Liepa,
// "Filling holes in meshes", SGP 2003): minimum-weight triangulation, density-matched refinement, bi-Laplacian fairing.
#pragma once

#include <pcl_patchdict/geometry/hole_triangulation.h>
#include <pcl_patchdict/geometry/mesh_fairing.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Fills the holes of a triangle mesh (Liepa 2003).
  *
  * Which boundary loops are holes: every loop, except
  *  - outer boundaries: a loop whose diameter (largest distance between two of its vertices) is at
  *    least outer_boundary_fraction (default 0.5) of the bounding-box diagonal of its connected
  *    component. The rim of an open scan (a disc, a terrain, a face mask) spans its component;
  *    a hole does not. A closed surface with one huge opening (a hemisphere) counts as open;
  *    setOuterBoundaryFraction(inf) fills every loop. Loop counts alone cannot tell: a sphere with
  *    one hole and a disc have the same topology;
  *  - loops through a non-manifold vertex (more than two boundary edges, or more than one fan of
  *    faces), or boundary chains that do not close (non-manifold edges): skipped, never filled;
  *  - loops beyond the limits: more than max_hole_edges edges, or a diameter above
  *    max_hole_diameter (input units).
  *
  * Each hole: its loop is triangulated without new vertices (triangulateHoleLoop: lexicographic
  * minimum of the largest dihedral angle, then the area), refined until the new vertices' spacing
  * matches the mean edge length around the loop (refineHolePatch, α = √2), and then all new
  * vertices are faired together (fairVertices: cotangent bi-Laplacian, everything else fixed).
  *
  * Output: the input vertices first, bit-identical and in input order, then the new vertices hole
  * by hole; the input faces in order, then the new faces. Fill faces are oriented like the mesh
  * faces across the loop. Holes are processed in parallel (OpenMP); the result does not depend on
  * the thread count. */
class HoleFilling {
public:
  using Ptr = std::shared_ptr<HoleFilling>;
  using ConstPtr = std::shared_ptr<const HoleFilling>;

  enum class SkipReason {
    None,               ///< filled
    OuterBoundary,      ///< the rim of an open surface (see the class comment)
    NonManifoldVertex,  ///< the loop passes a vertex with more than two boundary edges or fans
    OpenChain,          ///< boundary edges that do not close into a loop (non-manifold edges)
    TooManyEdges,       ///< more than max_hole_edges
    TooLarge,           ///< diameter above max_hole_diameter
    NoTriangulation     ///< every triangulation would duplicate an existing edge
  };

  /** One boundary loop and what happened to it. Indices refer to the output mesh. */
  struct Hole {
    std::vector<std::int32_t> boundary;      ///< loop vertices in walking order
    double length = 0.0;                     ///< of the loop
    double diameter = 0.0;                   ///< largest distance between two loop vertices
    SkipReason skipped = SkipReason::None;
    std::vector<std::int32_t> new_vertices;  ///< appended vertices of this hole's fill
    std::vector<std::int32_t> new_faces;     ///< appended faces of this hole's fill
    double max_dihedral_angle = 0.0;         ///< of the triangulation before refinement (radians)
    int refinement_rounds = 0;
    bool filled() const { return skipped == SkipReason::None; }
  };

  struct Report {
    std::size_t holes_found = 0;  ///< boundary loops (chains) of the input
    std::size_t holes_filled = 0;
    std::size_t holes_skipped = 0;
    std::size_t new_vertices = 0, new_faces = 0;
    std::vector<Hole> holes;      ///< in the order of computeBoundaryLoops (longest first)
    bool fairing_solved = true;   ///< false: the solver failed, new vertices stay where refinement put them
    std::size_t triangulation_pieces = 0;  ///< DP runs (more than filled holes when long loops were split)
    double seconds_triangulation = 0.0, seconds_refinement = 0.0, seconds_fairing = 0.0;
  };

  /** The mesh to fill, shared (PCL's rule: the filling keeps it alive until it is replaced). */
  void setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh) { input_ = mesh; }
  /** At most this many edges (0: no limit). */
  void setMaxHoleEdges(std::size_t edges) { max_hole_edges_ = edges; }
  std::size_t getMaxHoleEdges() const { return max_hole_edges_; }
  /** At most this diameter, in input units (infinity: no limit). */
  void setMaxHoleDiameter(double diameter) { max_hole_diameter_ = diameter; }
  double getMaxHoleDiameter() const { return max_hole_diameter_; }
  /** A loop spanning at least this fraction of its component's bbox diagonal is an outer boundary. */
  void setOuterBoundaryFraction(double fraction) { outer_boundary_fraction_ = fraction; }
  double getOuterBoundaryFraction() const { return outer_boundary_fraction_; }
  /** Liepa's α (√2): larger α, denser fill. */
  void setDensityFactor(double alpha) { refinement_.density_factor = alpha; }
  double getDensityFactor() const { return refinement_.density_factor; }
  void setRefine(bool refine) { refine_ = refine; }
  bool getRefine() const { return refine_; }
  void setFair(bool fair) { fair_ = fair; }
  bool getFair() const { return fair_; }
  void setFairingContinuity(int continuity) { fairing_.continuity = continuity; }
  int getFairingContinuity() const { return fairing_.continuity; }
  /** Loops longer than this are split before the O(n³) triangulation (see triangulateHoleLoop). */
  void setMaxTriangulationVertices(std::size_t count) { triangulation_.max_dp_vertices = count; }
  std::size_t getMaxTriangulationVertices() const { return triangulation_.max_dp_vertices; }

  /** Fills the holes. Throws Error for a missing input, a mesh without faces, non-finite
    * coordinates, face indices out of range, or parameters out of range. */
  void process(TriangleMesh& out, Report* report = nullptr) const;

private:
  std::shared_ptr<const TriangleMesh> input_;
  std::size_t max_hole_edges_ = 0;
  double max_hole_diameter_ = std::numeric_limits<double>::infinity();
  double outer_boundary_fraction_ = 0.5;
  bool refine_ = true;
  bool fair_ = true;
  HoleTriangulationOptions triangulation_;
  HoleRefinementOptions refinement_;
  FairingOptions fairing_;
};

/** "outer boundary", "non-manifold vertex", ... ("filled" for None). */
std::string toString(HoleFilling::SkipReason reason);

}  // namespace patchdict
}  // namespace pcl
