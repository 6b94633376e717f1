#include <pcl_patchdict/core/triangle_mesh.h>

#include <algorithm>
#include <unordered_set>

namespace pcl {
namespace patchdict {

void TriangleMesh::boundingBox(Eigen::Vector3d& min_pt, Eigen::Vector3d& max_pt) const
{
  if (vertices.empty()) {
    min_pt.setZero();
    max_pt.setZero();
    return;
  }
  min_pt = max_pt = vertices.front();
  for (const auto& v : vertices) {
    min_pt = min_pt.cwiseMin(v);
    max_pt = max_pt.cwiseMax(v);
  }
}

double TriangleMesh::boundingBoxDiagonal() const
{
  Eigen::Vector3d lo, hi;
  boundingBox(lo, hi);
  return (hi - lo).norm();
}

double TriangleMesh::meanEdgeLength() const
{
  std::unordered_set<std::uint64_t> seen;
  seen.reserve(faces.size() * 2);
  double sum = 0.0;
  std::size_t count = 0;
  for (const Face& f : faces)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = static_cast<std::uint32_t>(std::min(f[k], f[(k + 1) % 3]));
      const std::uint32_t b = static_cast<std::uint32_t>(std::max(f[k], f[(k + 1) % 3]));
      if (seen.insert((static_cast<std::uint64_t>(a) << 32) | b).second) {
        sum += (vertices[a] - vertices[b]).norm();
        ++count;
      }
    }
  return count ? sum / static_cast<double>(count) : 0.0;
}

double TriangleMesh::faceArea(std::size_t f) const
{
  const Face& t = faces[f];
  return 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
}

Eigen::Vector3d TriangleMesh::faceNormal(std::size_t f) const
{
  const Face& t = faces[f];
  const Eigen::Vector3d n = (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

double TriangleMesh::surfaceArea() const
{
  double area = 0.0;
  for (std::size_t f = 0; f < faces.size(); ++f)
    area += faceArea(f);
  return area;
}

}  // namespace patchdict
}  // namespace pcl
