#include <pcl_patchdict/core/vertex_normals.h>

#include <algorithm>
#include <cmath>

namespace pcl {
namespace patchdict {

std::vector<Eigen::Vector3d> computeVertexNormals(const TriangleMesh& mesh)
{
  std::vector<Eigen::Vector3d> normals(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Eigen::Vector3d n = mesh.faceNormal(f);
    if (n.isZero())
      continue;
    const Face& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = mesh.vertices[t[(k + 1) % 3]] - mesh.vertices[t[k]];
      const Eigen::Vector3d e2 = mesh.vertices[t[(k + 2) % 3]] - mesh.vertices[t[k]];
      // atan2 of |cross| and dot is accurate for angles near 0 and π, unlike acos.
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      normals[t[k]] += angle * n;
    }
  }
  for (auto& n : normals) {
    const double length = n.norm();
    n = length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::Zero();
  }
  return normals;
}

}  // namespace patchdict
}  // namespace pcl
