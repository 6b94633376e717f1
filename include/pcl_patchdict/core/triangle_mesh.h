// TriangleMesh — the indexed triangle mesh every stage of pcl_patchdict works on.
// Positions are kept in double so that float32 files round-trip bit-exactly and geometry is stable.
// Plain data without PCL: the conversions to pcl::PolygonMesh and pcl::PointCloud are in
// <pcl_patchdict/pcl/conversions.h>.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

using Face = std::array<std::int32_t, 3>;

/** \brief Indexed triangle mesh as plain data — a vertex/face soup: vertices, triangles, optional
  * normals, and no connectivity (MeshTopology builds the edges and neighbours when a stage needs
  * them). A mesh with no faces is a point cloud. Vertex indices in faces are 0-based. */
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Face> faces;
  /** Per-vertex normals; empty, or one per vertex. */
  std::vector<Eigen::Vector3d> normals;

  std::size_t numVertices() const { return vertices.size(); }
  std::size_t numFaces() const { return faces.size(); }
  bool hasNormals() const { return !normals.empty() && normals.size() == vertices.size(); }
  bool empty() const { return vertices.empty(); }

  /** Axis-aligned bounding box of all vertices (min, max); zero box for an empty mesh. */
  void boundingBox(Eigen::Vector3d& min_pt, Eigen::Vector3d& max_pt) const;
  /** Length of the bounding-box diagonal. */
  double boundingBoxDiagonal() const;
  /** Mean length of the (undirected, deduplicated) edges; 0 without faces. */
  double meanEdgeLength() const;
  /** Total surface area of the triangles. */
  double surfaceArea() const;
  /** Unit normal of face f (zero vector for a degenerate face). */
  Eigen::Vector3d faceNormal(std::size_t f) const;
  /** Area of face f. */
  double faceArea(std::size_t f) const;
};

}  // namespace patchdict
}  // namespace pcl
