#include <pcl_patchdict/coarse_mesh_estimation.h>
#include <pcl_patchdict/error.h>
#include <pcl_patchdict/mesh_topology.h>

#include <cmath>

namespace pcl {
namespace patchdict {

double meanDihedralAngle(const TriangleMesh& mesh)
{
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  double sum = 0.0;
  std::size_t count = 0;
  for (const MeshEdge& e : adjacency.edges) {
    if (e.faces.size() != 2)
      continue;
    const Eigen::Vector3d a = mesh.faceNormal(static_cast<std::size_t>(e.faces[0]));
    const Eigen::Vector3d b = mesh.faceNormal(static_cast<std::size_t>(e.faces[1]));
    if (a.isZero() || b.isZero())
      continue;
    sum += std::atan2(a.cross(b).norm(), a.dot(b));
    ++count;
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

void CoarseMeshEstimation::process(TriangleMesh& out, Report* report) const
{
  if (!input_ || input_->faces.empty())
    throw Error("coarse mesh estimation needs a mesh with faces");
  if (iterations_ < 0 || !(lambda_ > 0.0 && lambda_ <= 1.0) || !(mu_ < 0.0 && mu_ >= -1.0))
    throw Error("coarse mesh estimation: iterations ≥ 0, λ in (0, 1] and μ in [−1, 0) are required");
  for (std::size_t v = 0; v < input_->vertices.size(); ++v)
    if (!input_->vertices[v].allFinite())
      throw Error("coarse mesh estimation: vertex " + std::to_string(v) + " is not finite");

  // Neighbours each vertex is smoothed towards: its 1-ring inside the surface, its boundary
  // neighbours on a boundary (so rims slide along themselves, not inwards).
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(*input_);
  const std::size_t n = input_->vertices.size();
  std::vector<std::vector<std::int32_t>> ring(n), boundary_ring(n);
  for (const MeshEdge& e : adjacency.edges) {
    ring[static_cast<std::size_t>(e.v0)].push_back(e.v1);
    ring[static_cast<std::size_t>(e.v1)].push_back(e.v0);
    if (!e.isManifold() || e.isBoundary()) {
      boundary_ring[static_cast<std::size_t>(e.v0)].push_back(e.v1);
      boundary_ring[static_cast<std::size_t>(e.v1)].push_back(e.v0);
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (!boundary_ring[v].empty())
      ring[v] = boundary_ring[v];

  TriangleMesh mesh = *input_;
  std::vector<Eigen::Vector3d> next(n);
  auto step = [&](double factor) {
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(n); ++v) {
      const auto& neighbours = ring[static_cast<std::size_t>(v)];
      const Eigen::Vector3d& x = mesh.vertices[static_cast<std::size_t>(v)];
      if (neighbours.empty()) {
        next[static_cast<std::size_t>(v)] = x;
        continue;
      }
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto w : neighbours)
        mean += mesh.vertices[static_cast<std::size_t>(w)];
      mean /= static_cast<double>(neighbours.size());
      next[static_cast<std::size_t>(v)] = x + factor * (mean - x);
    }
    mesh.vertices.swap(next);
  };
  for (int iteration = 0; iteration < iterations_; ++iteration) {
    step(lambda_);
    if (method_ == Method::Taubin)
      step(mu_);
  }
  if (report) {
    const double before = input_->surfaceArea();
    report->area_change = before > 0.0 ? (mesh.surfaceArea() - before) / before : 0.0;
    report->mean_dihedral_before = meanDihedralAngle(*input_);
    report->mean_dihedral_after = meanDihedralAngle(mesh);
  }
  mesh.normals.clear();
  out = std::move(mesh);
}

}  // namespace patchdict
}  // namespace pcl
