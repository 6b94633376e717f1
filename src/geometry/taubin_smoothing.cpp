// TaubinSmoother (see taubin_smoothing.h). G. Taubin, "A signal processing approach to fair surface
// design", SIGGRAPH 1995; inverse-distance weights: K. Fujiwara, "Eigenvalues of Laplacians on a
// closed Riemannian manifold and its nets", Proc. AMS 1995 (as in Open3D's smoothing filters).
#include <pcl_patchdict/geometry/taubin_smoothing.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>

#include <string>

namespace pcl {
namespace patchdict {

TaubinSmoother::TaubinSmoother(const TriangleMesh& mesh, double lambda, double mu, Weights weights)
    : lambda_(lambda), mu_(mu)
{
  const std::size_t n = mesh.numVertices();
  for (const Face& f : mesh.faces)
    for (std::int32_t v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw Error("Taubin smoothing: a face refers to vertex " + std::to_string(v) + " of " + std::to_string(n));
  for (std::size_t v = 0; v < n; ++v)
    if (!mesh.vertices[v].allFinite())
      throw Error("Taubin smoothing: vertex " + std::to_string(v) + " is not finite");
  const std::vector<std::vector<std::int32_t>> ring = computeSmoothingNeighbours(mesh);
  offsets_.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    const auto& chosen = ring[v];
    double total = 0.0;
    const std::size_t first = neighbours_.size();
    neighbours_.insert(neighbours_.end(), chosen.begin(), chosen.end());
    if (weights == Weights::InverseDistance) {
      for (std::int32_t w : chosen) {
        const double weight = 1.0 / ((mesh.vertices[static_cast<std::size_t>(w)] - mesh.vertices[v]).norm() + 1e-12);
        weights_.push_back(weight);
        total += weight;
      }
      for (std::size_t i = first; i < weights_.size(); ++i)
        weights_[i] /= total;
    }
    offsets_[v + 1] = static_cast<std::int64_t>(neighbours_.size());
  }
}

void TaubinSmoother::step(std::vector<Eigen::Vector3d>& positions, double factor) const
{
  const std::size_t n = offsets_.size() - 1;
  if (positions.size() != n)
    throw Error("Taubin smoothing: " + std::to_string(positions.size()) + " positions for " + std::to_string(n) +
                " vertices");
  std::vector<Eigen::Vector3d> next(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(n); ++i) {
    const std::size_t v = static_cast<std::size_t>(i);
    if (offsets_[v] == offsets_[v + 1]) {
      next[v] = positions[v];
      continue;
    }
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    if (weights_.empty()) {
      for (std::int64_t k = offsets_[v]; k < offsets_[v + 1]; ++k)
        mean += positions[static_cast<std::size_t>(neighbours_[static_cast<std::size_t>(k)])];
      mean /= static_cast<double>(offsets_[v + 1] - offsets_[v]);
    } else {
      for (std::int64_t k = offsets_[v]; k < offsets_[v + 1]; ++k)
        mean += weights_[static_cast<std::size_t>(k)] *
                positions[static_cast<std::size_t>(neighbours_[static_cast<std::size_t>(k)])];
    }
    next[v] = positions[v] + factor * (mean - positions[v]);
  }
  positions.swap(next);
}

void TaubinSmoother::iterate(std::vector<Eigen::Vector3d>& positions) const
{
  step(positions, lambda_);
  step(positions, mu_);
}

}  // namespace patchdict
}  // namespace pcl
