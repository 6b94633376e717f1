// Mesh hygiene: inspect a mesh for what breaks later stages (unreferenced and non-finite vertices,
// degenerate and duplicate faces, non-manifold edges and vertices) and repair what can be repaired.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

struct MeshHygieneReport {
  std::size_t vertices = 0, faces = 0;
  std::size_t unreferenced_vertices = 0;  ///< used by no face
  std::size_t nonfinite_vertices = 0;     ///< a NaN or Inf coordinate
  std::size_t degenerate_faces = 0;       ///< a repeated vertex index, or zero area
  std::size_t duplicate_faces = 0;        ///< same vertex set as an earlier face (either orientation)
  std::size_t nonmanifold_edges = 0;      ///< used by more than two faces
  std::size_t nonmanifold_vertices = 0;   ///< faces around it form more than one fan
  std::size_t boundary_edges = 0;
  std::size_t boundary_loops = 0;
  std::size_t components = 0;

  /** One line, e.g. "35947 vertices, 69451 faces, 1113 unreferenced vertices, 5 boundary loops". */
  std::string summary() const;
};

/** Counts everything in MeshHygieneReport; the mesh is not changed. */
MeshHygieneReport inspectMesh(const TriangleMesh& mesh);

/** Number of face-connected fans around every vertex (0 for unused vertices; more than 1 marks a
  * non-manifold vertex, e.g. two cones touching at their tips). */
std::vector<int> computeVertexFanCounts(const TriangleMesh& mesh);

struct MeshCleanupOptions {
  bool remove_degenerate_faces = true;
  bool remove_duplicate_faces = true;
  bool remove_unreferenced_vertices = true;
};

/** What cleanMesh did, with the maps between old and new vertex indices. */
struct MeshCleanupResult {
  std::size_t degenerate_faces_removed = 0;
  std::size_t duplicate_faces_removed = 0;
  std::size_t unreferenced_vertices_removed = 0;
  std::vector<int> old_to_new;  ///< per input vertex: its new index, or −1 if dropped
  std::vector<int> new_to_old;  ///< per output vertex: its input index
  std::string summary() const;
};

/** Removes what the options ask for, keeping the order of what stays. Faces with a vertex of
  * non-finite position are degenerate. */
MeshCleanupResult cleanMesh(TriangleMesh& mesh, const MeshCleanupOptions& options = {});

/** Flips faces so that neighbours across manifold edges agree in orientation (breadth-first from
  * the lowest face of each component). Returns the number of faces flipped. */
std::size_t orientFacesConsistently(TriangleMesh& mesh);

}  // namespace patchdict
}  // namespace pcl
