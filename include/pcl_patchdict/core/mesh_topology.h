// Connectivity of a TriangleMesh: vertex 1-rings, edge–face adjacency, boundary loops and
// connected components. Pure functions of the face list; positions are never read.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <vector>

namespace pcl {
namespace patchdict {

/** Undirected edge v0 < v1 with the faces that use it (one: boundary; two: interior; more: non-manifold). */
struct MeshEdge {
  std::int32_t v0 = -1, v1 = -1;
  std::vector<std::int32_t> faces;
  bool isBoundary() const { return faces.size() == 1; }
  bool isManifold() const { return faces.size() <= 2; }
};

/** Edges of the mesh, and for each face the indices of its three edges (side k joins corners k and k+1). */
struct EdgeFaceAdjacency {
  std::vector<MeshEdge> edges;
  std::vector<std::array<std::int32_t, 3>> face_edges;
};

/** Every undirected edge with its incident faces; edges sorted by (v0, v1). Faces that repeat a
  * vertex index contribute no edges (their face_edges are −1). */
EdgeFaceAdjacency computeEdgeFaceAdjacency(const TriangleMesh& mesh);

/** Sorted, unique neighbour vertices of every vertex (its 1-ring); isolated vertices get none. */
std::vector<std::vector<std::int32_t>> computeVertexOneRings(const TriangleMesh& mesh);

/** Neighbours a smoothing filter averages: the 1-ring for interior vertices, only the boundary (or
  * non-manifold) edge neighbours for vertices on such edges, so rims slide along themselves instead
  * of shrinking inwards. Order: edges sorted by (v0, v1). */
std::vector<std::vector<std::int32_t>> computeSmoothingNeighbours(const TriangleMesh& mesh);

/** Faces incident to every vertex, in increasing face order. */
std::vector<std::vector<std::int32_t>> computeVertexFaces(const TriangleMesh& mesh);

/** A closed chain of boundary edges. */
struct BoundaryLoop {
  std::vector<std::int32_t> vertices;  ///< in walking order; the loop closes back to vertices.front()
  /** The walk met a vertex with more than two boundary edges: the loop is ambiguous there and
    * hole filling must skip it. */
  bool through_nonmanifold_vertex = false;
  /** The chain could not be closed (a boundary edge path that dead-ends at a non-manifold edge). */
  bool open = false;
  double length = 0.0;  ///< sum of its edge lengths
};

/** Boundary loops (chains of edges used by exactly one face), longest first; ties broken by the
  * smallest vertex index so the order is deterministic. */
std::vector<BoundaryLoop> computeBoundaryLoops(const TriangleMesh& mesh);

/** Connected components through shared vertices of faces. Fills the component of each face and
  * of each vertex (−1 for vertices no face uses); components are numbered by their smallest face.
  * Returns the number of components. */
int computeConnectedComponents(const TriangleMesh& mesh, std::vector<int>& face_component,
                               std::vector<int>& vertex_component);

/** Edge-connected regions of the flagged faces (two flagged faces sharing an edge are in one
  * region): each region's faces in increasing order, regions ordered by their smallest face.
  * `flagged` holds one flag per face (Error otherwise). */
std::vector<std::vector<std::int32_t>> flaggedFaceRegions(const TriangleMesh& mesh, const std::vector<char>& flagged);

}  // namespace patchdict
}  // namespace pcl
