// QuadMesh statistics (its polygon file: io/mesh_io.h, writeQuadMesh).
#include <pcl_patchdict/quads/quad_mesh.h>

#include <pcl_patchdict/core/error.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace pcl {
namespace patchdict {

Eigen::Vector3d QuadMesh::faceCentre(std::size_t f) const
{
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const std::int32_t v : faces[f])
    c += vertices[v];
  return faces[f].empty() ? c : Eigen::Vector3d(c / static_cast<double>(faces[f].size()));
}

Eigen::Vector3d QuadMesh::faceNormal(std::size_t f) const
{
  // Newell's method: the vector area of the polygon, exact for planar ones.
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const auto& face = faces[f];
  for (std::size_t k = 0; k < face.size(); ++k)
    n += vertices[face[k]].cross(vertices[face[(k + 1) % face.size()]]);
  const double length = n.norm();
  return length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
}

QuadMeshStatistics computeQuadMeshStatistics(const QuadMesh& mesh)
{
  QuadMeshStatistics s;
  s.vertices = mesh.vertices.size();
  s.faces = mesh.faces.size();
  const std::int64_t n = static_cast<std::int64_t>(mesh.vertices.size());
  std::map<std::pair<std::int32_t, std::int32_t>, int> edge_faces;
  std::set<std::vector<std::int32_t>> seen;
  std::vector<char> used(mesh.vertices.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (const std::int32_t v : face)
      if (v < 0 || v >= n)
        throw Error("quad mesh: face index " + std::to_string(v) + " is out of range");
    if (face.size() == 4)
      ++s.quads;
    else if (face.size() == 3)
      ++s.triangles;
    else
      ++s.other_faces;
    std::vector<std::int32_t> key = face;
    std::sort(key.begin(), key.end());
    const bool repeated = std::adjacent_find(key.begin(), key.end()) != key.end();
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < face.size(); ++k)
      area += mesh.vertices[face[k]].cross(mesh.vertices[face[(k + 1) % face.size()]]);
    if (repeated || face.size() < 3 || area.norm() == 0.0)
      ++s.degenerate_faces;
    if (!seen.insert(key).second)
      ++s.duplicate_faces;
    for (std::size_t k = 0; k < face.size(); ++k) {
      const std::int32_t a = face[k], b = face[(k + 1) % face.size()];
      used[a] = 1;
      if (a != b)
        ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
  }
  std::vector<int> valence(mesh.vertices.size(), 0);
  std::vector<char> on_boundary(mesh.vertices.size(), 0);
  double sum = 0.0;
  s.min_edge_length = edge_faces.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (const auto& [edge, count] : edge_faces) {
    ++valence[edge.first];
    ++valence[edge.second];
    if (count == 1) {
      ++s.boundary_edges;
      on_boundary[edge.first] = on_boundary[edge.second] = 1;
    } else if (count > 2) {
      ++s.nonmanifold_edges;
    }
    const double length = (mesh.vertices[edge.first] - mesh.vertices[edge.second]).norm();
    sum += length;
    s.min_edge_length = std::min(s.min_edge_length, length);
    s.max_edge_length = std::max(s.max_edge_length, length);
  }
  s.mean_edge_length = edge_faces.empty() ? 0.0 : sum / static_cast<double>(edge_faces.size());
  std::size_t valence4 = 0;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (used[v] && !on_boundary[v]) {
      ++s.interior_vertices;
      valence4 += valence[v] == 4;
    }
  s.quad_fraction = s.faces ? static_cast<double>(s.quads) / static_cast<double>(s.faces) : 0.0;
  s.interior_valence4_fraction =
      s.interior_vertices ? static_cast<double>(valence4) / static_cast<double>(s.interior_vertices) : 0.0;
  return s;
}

}  // namespace patchdict
}  // namespace pcl
