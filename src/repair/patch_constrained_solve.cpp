// Least-squares bi-Laplacian with soft point-to-plane constraints (see patch_constrained_solve.h).
// Least-squares meshes: Sorkine & Cohen-Or, SMI 2004; the uniform Laplacian as in Taubin 1995.
#include <pcl_patchdict/repair/patch_constrained_solve.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <string>

namespace pcl {
namespace patchdict {

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

}  // namespace

PatchConstrainedSolver::PatchConstrainedSolver(const TriangleMesh& mesh, const std::vector<bool>& is_free)
{
  const std::size_t n = mesh.numVertices();
  if (is_free.size() != n)
    throw Error("PatchConstrainedSolver: " + std::to_string(is_free.size()) + " free flags for " +
                std::to_string(n) + " vertices");
  for (const Face& f : mesh.faces)
    for (std::int32_t v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        throw Error("PatchConstrainedSolver: a face refers to vertex " + std::to_string(v) + " of " +
                    std::to_string(n));
  rings_ = computeVertexOneRings(mesh);
  free_index_.assign(n, -1);
  for (std::size_t v = 0; v < n; ++v)
    if (is_free[v]) {
      free_index_[v] = static_cast<std::int32_t>(free_vertices_.size());
      free_vertices_.push_back(static_cast<std::int32_t>(v));
    }

  // Every connected part with a free vertex needs a fixed one, else constants are in the kernel.
  std::vector<int> component(n, -1);
  std::vector<std::int32_t> stack;
  int components = 0;
  std::vector<bool> has_fixed, has_free;
  for (std::size_t start = 0; start < n; ++start) {
    if (component[start] >= 0)
      continue;
    const int c = components++;
    has_fixed.push_back(false);
    has_free.push_back(false);
    component[start] = c;
    stack.assign(1, static_cast<std::int32_t>(start));
    while (!stack.empty()) {
      const std::int32_t v = stack.back();
      stack.pop_back();
      if (is_free[static_cast<std::size_t>(v)])
        has_free[static_cast<std::size_t>(c)] = true;
      else
        has_fixed[static_cast<std::size_t>(c)] = true;
      for (std::int32_t w : rings_[static_cast<std::size_t>(v)])
        if (component[static_cast<std::size_t>(w)] < 0) {
          component[static_cast<std::size_t>(w)] = c;
          stack.push_back(w);
        }
    }
  }
  for (int c = 0; c < components; ++c)
    if (has_free[static_cast<std::size_t>(c)] && !has_fixed[static_cast<std::size_t>(c)])
      throw Error("a connected part of the mesh has no known vertex: its missing vertices cannot be recovered");
}

namespace {

/** The bi-Laplacian normal equations (`normal`, `rhs`: one column per coordinate) with the
  * point-to-plane constraints, which couple the coordinates: unknown 3f + c is coordinate c of
  * free vertex f. Writes the free vertices of `positions`. */
void solveCoupled(const SparseMatrix& normal, const Eigen::MatrixXd& rhs,
                  const std::vector<PointToPlaneConstraint>& constraints, double constraint_weight,
                  const std::vector<std::int32_t>& free_index_, const std::vector<std::int32_t>& free_vertices_,
                  std::vector<Eigen::Vector3d>& positions)
{
  const std::size_t num_free = free_vertices_.size();
  std::vector<Triplet> h_entries;
  h_entries.reserve(static_cast<std::size_t>(normal.nonZeros()) * 3 + constraints.size() * 9);
  for (int k = 0; k < normal.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(normal, k); it; ++it)
      for (int c = 0; c < 3; ++c)
        h_entries.emplace_back(3 * static_cast<int>(it.row()) + c, 3 * static_cast<int>(it.col()) + c, it.value());
  Eigen::VectorXd g(static_cast<Eigen::Index>(3 * num_free));
  for (std::size_t f = 0; f < num_free; ++f)
    g.segment<3>(static_cast<Eigen::Index>(3 * f)) = rhs.row(static_cast<Eigen::Index>(f)).transpose();
  for (const PointToPlaneConstraint& c : constraints) {
    if (!(c.weight > 0.0))
      continue;
    const double w = constraint_weight * c.weight;
    const int f = free_index_[static_cast<std::size_t>(c.vertex)];
    const Eigen::Matrix3d block = w * c.normal * c.normal.transpose();
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 3; ++s)
        h_entries.emplace_back(3 * f + r, 3 * f + s, block(r, s));
    g.segment<3>(3 * f) += w * c.normal.dot(c.point) * c.normal;
  }
  SparseMatrix h(static_cast<Eigen::Index>(3 * num_free), static_cast<Eigen::Index>(3 * num_free));
  h.setFromTriplets(h_entries.begin(), h_entries.end());
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(h);
  if (ldlt.info() != Eigen::Success)
    throw Error("the constrained bi-Laplacian system could not be factorised");
  const Eigen::VectorXd x = ldlt.solve(g);
  if (ldlt.info() != Eigen::Success || !x.allFinite())
    throw Error("the constrained bi-Laplacian system could not be solved");
  for (std::size_t f = 0; f < num_free; ++f)
    positions[static_cast<std::size_t>(free_vertices_[f])] = x.segment<3>(static_cast<Eigen::Index>(3 * f));
}

}  // namespace

void PatchConstrainedSolver::solve(std::vector<Eigen::Vector3d>& positions,
                                   const std::vector<PointToPlaneConstraint>& constraints,
                                   double constraint_weight) const
{
  const std::size_t n = free_index_.size();
  if (positions.size() != n)
    throw Error("PatchConstrainedSolver: " + std::to_string(positions.size()) + " positions for " +
                std::to_string(n) + " vertices");
  const std::size_t num_free = free_vertices_.size();
  if (num_free == 0)
    return;

  // Rows of L that involve a free vertex: the free vertices and their neighbours, in vertex order.
  std::vector<bool> row_used(n, false);
  for (std::int32_t v : free_vertices_) {
    row_used[static_cast<std::size_t>(v)] = true;
    for (std::int32_t w : rings_[static_cast<std::size_t>(v)])
      row_used[static_cast<std::size_t>(w)] = true;
  }
  std::vector<Triplet> a_entries;
  std::vector<Eigen::Vector3d> b;  // A x_free ≈ b: minus the fixed vertices' part of each row
  for (std::size_t i = 0; i < n; ++i) {
    if (!row_used[i])
      continue;
    const int row = static_cast<int>(b.size());
    Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
    const auto& ring = rings_[i];
    const double inv_degree = ring.empty() ? 0.0 : 1.0 / static_cast<double>(ring.size());
    if (free_index_[i] >= 0)
      a_entries.emplace_back(row, free_index_[i], 1.0);
    else
      rhs -= positions[i];
    for (std::int32_t w : ring) {
      if (free_index_[static_cast<std::size_t>(w)] >= 0)
        a_entries.emplace_back(row, free_index_[static_cast<std::size_t>(w)], -inv_degree);
      else
        rhs += inv_degree * positions[static_cast<std::size_t>(w)];
    }
    b.push_back(rhs);
  }
  SparseMatrix a(static_cast<Eigen::Index>(b.size()), static_cast<Eigen::Index>(num_free));
  a.setFromTriplets(a_entries.begin(), a_entries.end());
  Eigen::MatrixXd b_matrix(static_cast<Eigen::Index>(b.size()), 3);
  for (std::size_t r = 0; r < b.size(); ++r)
    b_matrix.row(static_cast<Eigen::Index>(r)) = b[r].transpose();
  const SparseMatrix at = a.transpose();
  const SparseMatrix normal = (at * a).pruned();
  const Eigen::MatrixXd rhs = at * b_matrix;  // num_free × 3

  bool use_constraints = false;
  for (const PointToPlaneConstraint& c : constraints) {
    if (c.vertex < 0 || static_cast<std::size_t>(c.vertex) >= n || free_index_[static_cast<std::size_t>(c.vertex)] < 0)
      throw Error("PatchConstrainedSolver: a constraint on vertex " + std::to_string(c.vertex) +
                  ", which is not free");
    if (c.weight > 0.0 && constraint_weight > 0.0)
      use_constraints = true;
  }

  if (!use_constraints) {
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(normal);
    if (ldlt.info() != Eigen::Success)
      throw Error("the bi-Laplacian system could not be factorised");
    const Eigen::MatrixXd x = ldlt.solve(rhs);
    if (ldlt.info() != Eigen::Success || !x.allFinite())
      throw Error("the bi-Laplacian system could not be solved");
    for (std::size_t f = 0; f < num_free; ++f)
      positions[static_cast<std::size_t>(free_vertices_[f])] = x.row(static_cast<Eigen::Index>(f)).transpose();
    return;
  }

  solveCoupled(normal, rhs, constraints, constraint_weight, free_index_, free_vertices_, positions);
}

}  // namespace patchdict
}  // namespace pcl
