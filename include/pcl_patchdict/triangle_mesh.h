// TriangleMesh — the indexed triangle mesh every stage of pcl_patchdict works on.
// Positions are kept in double so that float32 files round-trip bit-exactly and geometry is stable.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <pcl/PolygonMesh.h>
#include <pcl/point_cloud.h>

namespace pcl {
namespace patchdict {

using Face = std::array<std::int32_t, 3>;

/** \brief Indexed triangle mesh (PMP-style plain data): vertices, triangles, optional normals.
  * A mesh with no faces is a point cloud. Vertex indices in faces are 0-based. */
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

/** \brief Convert to a pcl::PolygonMesh (cloud fields x y z as float32, plus normal_x.. when present). */
void toPolygonMesh(const TriangleMesh& mesh, pcl::PolygonMesh& out);
/** \brief Convert from a pcl::PolygonMesh. Polygons with more than 3 vertices are fan-triangulated;
  * throws pcl::patchdict::Error if the cloud has no x/y/z fields or a face index is out of range. */
void fromPolygonMesh(const pcl::PolygonMesh& in, TriangleMesh& mesh);

/** \brief Copy the vertices (and normals, when PointT has them) into a cloud. */
template <typename PointT>
void toPointCloud(const TriangleMesh& mesh, pcl::PointCloud<PointT>& cloud);
/** \brief A face-less mesh from the cloud's finite points (and normals, when PointT has them).
  * \param[out] index_map optional: for each mesh vertex, the index of the point it came from. */
template <typename PointT>
void fromPointCloud(const pcl::PointCloud<PointT>& cloud, TriangleMesh& mesh,
                    std::vector<int>* index_map = nullptr);

}  // namespace patchdict
}  // namespace pcl

#include <pcl_patchdict/impl/triangle_mesh.hpp>
