// QuadMesh — a quad-dominant polygon mesh (the output of QuadRemesher) and its quality statistics:
// face sizes, valences, edge lengths, degenerate and duplicate faces.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** Polygon mesh: faces list their vertices counter-clockwise seen from the side the vertex
  * normals point to. Mostly quads; triangles and the odd larger face where the lattice breaks. */
struct QuadMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3d> normals;  ///< unit, one per vertex
  std::vector<std::vector<std::int32_t>> faces;

  std::size_t numVertices() const { return vertices.size(); }
  std::size_t numFaces() const { return faces.size(); }
  /** Centroid of the face's vertices. */
  Eigen::Vector3d faceCentre(std::size_t f) const;
  /** Unit normal of the face: Newell's method (robust for non-planar quads); zero if degenerate. */
  Eigen::Vector3d faceNormal(std::size_t f) const;
};

struct QuadMeshStatistics {
  std::size_t vertices = 0, faces = 0, quads = 0, triangles = 0, other_faces = 0;
  double quad_fraction = 0.0;              ///< quads / faces
  std::size_t interior_vertices = 0;       ///< vertices on no boundary edge and used by a face
  double interior_valence4_fraction = 0.0; ///< of the interior vertices, those with 4 edges
  std::size_t boundary_edges = 0, nonmanifold_edges = 0;
  double mean_edge_length = 0.0, min_edge_length = 0.0, max_edge_length = 0.0;
  std::size_t degenerate_faces = 0;  ///< a repeated vertex, fewer than 3 distinct vertices, or zero area
  std::size_t duplicate_faces = 0;   ///< faces with the same vertex set as an earlier face
};

/** Statistics of a quad mesh. Throws Error for an out-of-range face index. */
QuadMeshStatistics computeQuadMeshStatistics(const QuadMesh& mesh);


}  // namespace patchdict
}  // namespace pcl
