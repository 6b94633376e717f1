// Fairing by the k-harmonic equation L^(k+1) x = 0 with cotangent weights and mixed Voronoi areas
// (Botsch et al. 2010, "Polygon Mesh Processing", ch. 4; the weights of Meyer et al. 2003).
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/mesh_fairing.h>
#include <pcl_patchdict/core/mesh_topology.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>

namespace pcl {
namespace patchdict {

namespace {

// Cotangent of the angle at `at` in triangle (at, p, q). Clamped: a needle triangle must not give
// one edge a weight that swamps the rest of the row (|cot| ≤ 1e3 is an angle of 0.06°).
double cotangent(const Eigen::Vector3d& at, const Eigen::Vector3d& p, const Eigen::Vector3d& q)
{
  const Eigen::Vector3d u = p - at, v = q - at;
  const double sine = u.cross(v).norm();
  const double cosine = u.dot(v);
  if (!(sine > 0.0))
    return cosine >= 0.0 ? 1e3 : -1e3;
  return std::clamp(cosine / sine, -1e3, 1e3);
}

// Mixed Voronoi area of corner 0 of triangle (a, b, c) (Meyer et al. 2003, figure 4).
double mixedArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const double area = 0.5 * (b - a).cross(c - a).norm();
  if (!(area > 0.0))
    return 0.0;
  const double dot_a = (b - a).dot(c - a), dot_b = (a - b).dot(c - b), dot_c = (a - c).dot(b - c);
  if (dot_a < 0.0)
    return 0.5 * area;
  if (dot_b < 0.0 || dot_c < 0.0)
    return 0.25 * area;
  return 0.125 * ((b - a).squaredNorm() * cotangent(c, a, b) + (c - a).squaredNorm() * cotangent(b, a, c));
}

/** Local numbering: the free vertices first, then the rings around them up to distance
  * continuity + 1 (the Laplacian is needed at distance ≤ k, positions at ≤ k + 1). Returns how
  * many local vertices need a Laplacian row. */
std::size_t numberRings(const TriangleMesh& mesh, const std::vector<std::vector<std::int32_t>>& vertex_faces,
                        const std::vector<std::int32_t>& free, int continuity, std::vector<int>& local,
                        std::vector<std::int32_t>& order)
{
  local.assign(mesh.vertices.size(), -1);
  for (const std::int32_t v : free) {
    local[v] = static_cast<int>(order.size());
    order.push_back(v);
  }
  std::size_t ring_begin = 0, laplacian_rows = 0;
  for (int level = 0; level <= continuity; ++level) {
    const std::size_t ring_end = order.size();
    laplacian_rows = ring_end;
    for (std::size_t i = ring_begin; i < ring_end; ++i)
      for (const std::int32_t f : vertex_faces[order[i]])
        for (const std::int32_t w : mesh.faces[f])
          if (local[w] < 0) {
            local[w] = static_cast<int>(order.size());
            order.push_back(w);
          }
    ring_begin = ring_end;
  }
  return laplacian_rows;
}

/** The first `rows` rows of L = D⁻¹W over the local vertices (cotangent or uniform weights), and
  * each row's area D. */
void laplacianRows(const TriangleMesh& mesh, const std::vector<std::vector<std::int32_t>>& vertex_faces,
                   const std::vector<std::int32_t>& order, const std::vector<int>& local, std::size_t rows,
                   FairingWeights weights, std::vector<Eigen::Triplet<double>>& triplets,
                   std::vector<double>& row_area)
{
  row_area.assign(rows, 1.0);
  for (std::size_t i = 0; i < rows; ++i) {
    const std::int32_t v = order[i];
    const Eigen::Vector3d& p = mesh.vertices[v];
    std::vector<std::pair<int, double>> row;
    double area = 0.0;
    for (const std::int32_t f : vertex_faces[v]) {
      const Face& t = mesh.faces[f];
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
        continue;
      int corner = 0;
      while (t[corner] != v)
        ++corner;
      const std::int32_t a = t[(corner + 1) % 3], b = t[(corner + 2) % 3];
      if (weights == FairingWeights::Uniform) {
        row.emplace_back(local[a], 1.0);
        row.emplace_back(local[b], 1.0);
        continue;
      }
      const Eigen::Vector3d &pa = mesh.vertices[a], &pb = mesh.vertices[b];
      row.emplace_back(local[b], 0.5 * cotangent(pa, p, pb));
      row.emplace_back(local[a], 0.5 * cotangent(pb, p, pa));
      area += mixedArea(p, pa, pb);
    }
    if (weights == FairingWeights::Uniform) {
      // Each neighbour counts once, however many faces it shares with v.
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
      area = static_cast<double>(row.size());
    }
    if (!(area > 0.0))
      area = 1.0;
    row_area[i] = area;
    double diagonal = 0.0;
    for (const auto& [column, weight] : row) {
      triplets.emplace_back(static_cast<int>(i), column, weight / area);
      diagonal -= weight / area;
    }
    triplets.emplace_back(static_cast<int>(i), static_cast<int>(i), diagonal);
  }
}

/** Solves A x = rhs by sparse Cholesky (LDLᵀ), or by sparse LU when A is not (numerically)
  * symmetric definite, e.g. a degenerate region. False when neither gives a finite solution. */
bool solveSparse(const Eigen::SparseMatrix<double>& a, const Eigen::MatrixX3d& rhs, Eigen::MatrixX3d& solution)
{
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> cholesky(a);
  if (cholesky.info() == Eigen::Success)
    solution = cholesky.solve(rhs);
  if (cholesky.info() != Eigen::Success || !solution.allFinite()) {
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
    lu.analyzePattern(a);
    lu.factorize(a);
    if (lu.info() != Eigen::Success)
      return false;
    solution = lu.solve(rhs);
    if (lu.info() != Eigen::Success || !solution.allFinite())
      return false;
  }
  return true;
}

}  // namespace

bool fairVertices(TriangleMesh& mesh, const std::vector<std::int32_t>& free_vertices, const FairingOptions& options,
                  FairingReport* report)
{
  FairingReport local_report;
  FairingReport& out_report = report ? *report : local_report;
  out_report = FairingReport{};
  if (options.continuity < 0 || options.continuity > 2)
    throw Error("fairing: continuity must be 0, 1 or 2 (got " + std::to_string(options.continuity) + ")");
  const std::size_t n = mesh.vertices.size();
  std::vector<std::int32_t> free = free_vertices;
  for (const std::int32_t v : free)
    if (v < 0 || static_cast<std::size_t>(v) >= n)
      throw Error("fairing: vertex index " + std::to_string(v) + " is out of range");
  std::sort(free.begin(), free.end());
  free.erase(std::unique(free.begin(), free.end()), free.end());
  out_report.free_vertices = free.size();
  if (free.empty()) {
    out_report.solved = true;
    return true;
  }

  const auto vertex_faces = computeVertexFaces(mesh);
  std::vector<int> local;
  std::vector<std::int32_t> order;  // local index → global
  const std::size_t laplacian_rows = numberRings(mesh, vertex_faces, free, options.continuity, local, order);
  const std::size_t m = order.size();
  out_report.fixed_vertices_used = m - free.size();

  // L over the local vertices; only the first laplacian_rows rows are filled.
  std::vector<Eigen::Triplet<double>> triplets;
  std::vector<double> row_area;
  laplacianRows(mesh, vertex_faces, order, local, laplacian_rows, options.weights, triplets, row_area);
  using SparseMatrix = Eigen::SparseMatrix<double>;
  SparseMatrix laplacian(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
  laplacian.setFromTriplets(triplets.begin(), triplets.end());

  // Rows of L^(k+1) = (D⁻¹W)^(k+1) at the free vertices, multiplied by their areas D: W (D⁻¹W)^k,
  // whose free-by-free block is symmetric, so a sparse Cholesky (LDLᵀ) solves it. The free rows
  // are the first local indices.
  const auto free_count = static_cast<Eigen::Index>(free.size());
  std::vector<Eigen::Triplet<double>> free_rows;
  for (const auto& triplet : triplets)
    if (triplet.row() < free_count)
      free_rows.emplace_back(triplet.row(), triplet.col(), triplet.value() * row_area[triplet.row()]);
  SparseMatrix system(free_count, static_cast<Eigen::Index>(m));
  system.setFromTriplets(free_rows.begin(), free_rows.end());
  for (int level = 0; level < options.continuity; ++level)
    system = SparseMatrix(system * laplacian);

  Eigen::MatrixX3d fixed_positions(static_cast<Eigen::Index>(m) - free_count, 3);
  for (std::size_t i = free.size(); i < m; ++i)
    fixed_positions.row(static_cast<Eigen::Index>(i) - free_count) = mesh.vertices[order[i]].transpose();
  const SparseMatrix unknown_part = system.leftCols(free_count);
  const Eigen::MatrixX3d rhs = -(system.rightCols(static_cast<Eigen::Index>(m) - free_count) * fixed_positions);
  Eigen::MatrixX3d solution;
  if (!solveSparse(unknown_part, rhs, solution))
    return false;
  for (std::size_t i = 0; i < free.size(); ++i)
    mesh.vertices[free[i]] = solution.row(static_cast<Eigen::Index>(i)).transpose();
  out_report.solved = true;
  return true;
}

}  // namespace patchdict
}  // namespace pcl
