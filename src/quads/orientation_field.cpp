// Multi-resolution hierarchy and extrinsic 4-RoSy orientation field (Jakob et al. 2015, §4–5),
// implemented from the paper's description (§3, §5) — not from the reference code.
#include <pcl_patchdict/quads/orientation_field.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include "quads/field_common.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <string>

namespace pcl {
namespace patchdict {

namespace {

constexpr double kPi = 3.14159265358979323846;

using detail::tangentFrame;
using detail::uniform01;

using detail::projectToTangent;

/** Greedy colouring in vertex order: each vertex takes the smallest colour none of its already
  * coloured neighbours has. Deterministic; uses at most max-degree + 1 colours. */
void colourLevel(FieldLevel& level)
{
  const std::int32_t n = static_cast<std::int32_t>(level.numVertices());
  std::vector<std::int32_t> colour(n, -1);
  std::vector<char> used;
  std::int32_t num_colours = 0;
  for (std::int32_t i = 0; i < n; ++i) {
    used.assign(static_cast<std::size_t>(num_colours) + 1, 0);
    for (std::int32_t e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
      const std::int32_t c = colour[level.adjacency[e]];
      if (c >= 0)
        used[c] = 1;
    }
    std::int32_t c = 0;
    while (used[c])
      ++c;
    colour[i] = c;
    num_colours = std::max(num_colours, c + 1);
  }
  level.phases.assign(num_colours, {});
  for (std::int32_t i = 0; i < n; ++i)
    level.phases[colour[i]].push_back(i);
}

/** Level 0: mesh vertices, angle-weighted normals, barycentric dual areas, uniform weights. */
FieldLevel makeFinestLevel(const TriangleMesh& mesh)
{
  FieldLevel level;
  level.positions = mesh.vertices;
  level.normals = computeVertexNormals(mesh);
  level.areas.assign(mesh.vertices.size(), 0.0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const double third = mesh.faceArea(f) / 3.0;
    for (const std::int32_t v : mesh.faces[f])
      level.areas[v] += third;
  }
  const auto rings = computeVertexOneRings(mesh);
  level.adjacency_offsets.assign(rings.size() + 1, 0);
  for (std::size_t i = 0; i < rings.size(); ++i)
    level.adjacency_offsets[i + 1] = level.adjacency_offsets[i] + static_cast<std::int32_t>(rings[i].size());
  level.adjacency.reserve(level.adjacency_offsets.back());
  for (const auto& ring : rings)
    level.adjacency.insert(level.adjacency.end(), ring.begin(), ring.end());
  level.adjacency_weights.assign(level.adjacency.size(), 1.0);
  return level;
}

/** downsample_graph (Jakob et al. 2015 §5): greedy edge matching by descending
  * (n_i·n_k)·max(A_i/A_k, A_k/A_i); returns false when no edge could be collapsed. */
bool coarsenLevel(FieldLevel& fine, FieldLevel& coarse)
{
  const std::int32_t n = static_cast<std::int32_t>(fine.numVertices());

  struct ScoredEdge {
    std::int32_t i, k;
    double score;
  };
  std::vector<ScoredEdge> edges;
  edges.reserve(fine.adjacency.size() / 2);
  for (std::int32_t i = 0; i < n; ++i) {
    for (std::int32_t e = fine.adjacency_offsets[i]; e < fine.adjacency_offsets[i + 1]; ++e) {
      const std::int32_t k = fine.adjacency[e];
      if (k <= i)
        continue;  // each undirected edge once, in (i, k) order: the tie-break order
      const double a = fine.areas[i], b = fine.areas[k];
      const double lo = std::min(a, b), hi = std::max(a, b);
      // Zero areas only come from degenerate faces; keep the score finite and ordered.
      const double ratio = lo > 0.0 ? hi / lo : (hi > 0.0 ? 1e300 : 1.0);
      edges.push_back({i, k, fine.normals[i].dot(fine.normals[k]) * ratio});
    }
  }
  if (edges.empty())
    return false;
  std::stable_sort(edges.begin(), edges.end(),
                   [](const ScoredEdge& x, const ScoredEdge& y) { return x.score > y.score; });

  std::vector<std::int32_t> match(n, -1);
  bool collapsed = false;
  for (const ScoredEdge& e : edges) {
    if (match[e.i] < 0 && match[e.k] < 0) {
      match[e.i] = e.k;
      match[e.k] = e.i;
      collapsed = true;
    }
  }
  if (!collapsed)
    return false;

  // Coarse vertices in order of their smallest child keeps the spatial locality of the input order.
  fine.parents.assign(n, -1);
  coarse = FieldLevel();
  for (std::int32_t i = 0; i < n; ++i) {
    if (fine.parents[i] >= 0)
      continue;
    const std::int32_t c = static_cast<std::int32_t>(coarse.children.size());
    const std::int32_t k = match[i];  // k > i whenever it exists, since i is the first seen
    fine.parents[i] = c;
    if (k >= 0) {
      fine.parents[k] = c;
      const double area = fine.areas[i] + fine.areas[k];
      // Area weights; a pair of zero-area vertices falls back to the midpoint.
      const double wi = area > 0.0 ? fine.areas[i] / area : 0.5, wk = 1.0 - wi;
      coarse.positions.push_back(wi * fine.positions[i] + wk * fine.positions[k]);
      Eigen::Vector3d normal = fine.areas[i] * fine.normals[i] + fine.areas[k] * fine.normals[k];
      if (normal.norm() <= 1e-300)
        normal = fine.normals[i] + fine.normals[k];
      const double length = normal.norm();
      coarse.normals.push_back(length > 0.0 ? Eigen::Vector3d(normal / length) : fine.normals[i]);
      coarse.areas.push_back(area);
      coarse.children.push_back({i, k});
    } else {
      coarse.positions.push_back(fine.positions[i]);
      coarse.normals.push_back(fine.normals[i]);
      coarse.areas.push_back(fine.areas[i]);
      coarse.children.push_back({i, -1});
    }
  }

  // Merge the children's adjacency: drop the internal edge, sum the weights of parallel edges.
  const std::int32_t m = static_cast<std::int32_t>(coarse.children.size());
  coarse.adjacency_offsets.assign(static_cast<std::size_t>(m) + 1, 0);
  std::vector<std::pair<std::int32_t, double>> merged;
  for (std::int32_t c = 0; c < m; ++c) {
    merged.clear();
    for (const std::int32_t child : coarse.children[c]) {
      if (child < 0)
        continue;
      for (std::int32_t e = fine.adjacency_offsets[child]; e < fine.adjacency_offsets[child + 1]; ++e) {
        const std::int32_t target = fine.parents[fine.adjacency[e]];
        if (target != c)
          merged.emplace_back(target, fine.adjacency_weights[e]);
      }
    }
    std::sort(merged.begin(), merged.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    for (std::size_t j = 0; j < merged.size();) {
      double weight = 0.0;
      const std::int32_t target = merged[j].first;
      // Summation in sorted child/edge order is fixed, so the weights are reproducible.
      for (; j < merged.size() && merged[j].first == target; ++j)
        weight += merged[j].second;
      coarse.adjacency.push_back(target);
      coarse.adjacency_weights.push_back(weight);
    }
    coarse.adjacency_offsets[c + 1] = static_cast<std::int32_t>(coarse.adjacency.size());
  }
  return true;
}

/** One Gauss–Seidel update of vertex i (Jakob et al. 2015 §3). */
void smoothOrientationVertex(const FieldLevel& level, std::vector<Eigen::Vector3d>& q, std::int32_t i)
{
  const Eigen::Vector3d& n_i = level.normals[i];
  Eigen::Vector3d sum = q[i];
  double weight_sum = 0.0;
  for (std::int32_t e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
    const std::int32_t j = level.adjacency[e];
    const double w = level.adjacency_weights[e];
    const auto ab = compatOrientationExtrinsic4(sum, n_i, q[j], level.normals[j]);
    // Running weighted mean of the matched representatives, kept in the tangent plane of i.
    sum = ab.first * weight_sum + ab.second * w;
    sum -= n_i * n_i.dot(sum);
    weight_sum += w;
    const double length = sum.norm();
    if (length > 0.0)
      sum /= length;
  }
  if (weight_sum > 0.0 && sum.squaredNorm() > 0.0)
    q[i] = sum;
}

}  // namespace

FieldHierarchy buildFieldHierarchy(const TriangleMesh& mesh)
{
  if (mesh.faces.empty())
    throw Error("orientation field: the mesh has no faces");
  const std::int64_t num_vertices = static_cast<std::int64_t>(mesh.vertices.size());
  for (const Face& face : mesh.faces)
    for (const std::int32_t v : face)
      if (v < 0 || v >= num_vertices)
        throw Error("orientation field: face index " + std::to_string(v) + " is out of range");

  FieldHierarchy hierarchy;
  hierarchy.levels.push_back(makeFinestLevel(mesh));
  colourLevel(hierarchy.levels.back());
  while (hierarchy.levels.back().numVertices() > 1 &&
         static_cast<int>(hierarchy.levels.size()) < FieldHierarchy::kMaxLevels) {
    FieldLevel coarse;
    if (!coarsenLevel(hierarchy.levels.back(), coarse)) {
      hierarchy.levels.back().parents.clear();
      break;
    }
    colourLevel(coarse);
    hierarchy.levels.push_back(std::move(coarse));
  }
  return hierarchy;
}

namespace {

// Of {q0, n0×q0} × {q1, n1×q1}, the pair most nearly parallel or antiparallel (Jakob et al. 2015,
// extrinsic 4-RoSy comparison): the 4-fold symmetry reduced to two candidates on each side.
void bestAlignedPair(const Eigen::Vector3d (&A)[2], const Eigen::Vector3d (&B)[2], int& best_a, int& best_b)
{
  double best = -1.0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      const double score = std::abs(A[a].dot(B[b]));
      if (score > best) {
        best = score;
        best_a = a;
        best_b = b;
      }
    }
}

}  // namespace

std::pair<Eigen::Vector3d, Eigen::Vector3d> compatOrientationExtrinsic4(const Eigen::Vector3d& q0,
                                                                        const Eigen::Vector3d& n0,
                                                                        const Eigen::Vector3d& q1,
                                                                        const Eigen::Vector3d& n1)
{
  const Eigen::Vector3d A[2] = {q0, n0.cross(q0)};
  const Eigen::Vector3d B[2] = {q1, n1.cross(q1)};
  int best_a = 0, best_b = 0;
  bestAlignedPair(A, B, best_a, best_b);
  const double dot = A[best_a].dot(B[best_b]);
  return {A[best_a], dot < 0.0 ? Eigen::Vector3d(-B[best_b]) : B[best_b]};
}

int compatOrientationExtrinsicIndex4(const Eigen::Vector3d& q0, const Eigen::Vector3d& n0,
                                     const Eigen::Vector3d& q1, const Eigen::Vector3d& n1)
{
  const Eigen::Vector3d A[2] = {q0, n0.cross(q0)};
  const Eigen::Vector3d B[2] = {q1, n1.cross(q1)};
  int best_a = 0, best_b = 0;
  bestAlignedPair(A, B, best_a, best_b);
  // rot^best_a(q0) ≈ ±rot^best_b(q1); a negative sign is two more quarter turns of q1.
  if (A[best_a].dot(B[best_b]) < 0.0)
    best_b += 2;
  return ((best_b - best_a) % 4 + 4) % 4;
}

std::vector<Eigen::Vector3d> randomTangentField(const std::vector<Eigen::Vector3d>& normals, std::uint64_t seed)
{
  std::mt19937_64 rng(seed);
  std::vector<Eigen::Vector3d> q(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) {
    const double angle = 2.0 * kPi * uniform01(rng);
    Eigen::Vector3d e1 = Eigen::Vector3d::UnitX(), e2 = Eigen::Vector3d::UnitY();
    if (normals[i].squaredNorm() > 0.0)
      tangentFrame(normals[i], e1, e2);
    q[i] = std::cos(angle) * e1 + std::sin(angle) * e2;
  }
  return q;
}

std::vector<Eigen::Vector3d> computeOrientationField(const FieldHierarchy& hierarchy,
                                                     const OrientationFieldParameters& parameters)
{
  if (hierarchy.levels.empty())
    throw Error("orientation field: empty hierarchy");
  if (parameters.iterations_per_level < 0)
    throw Error("orientation field: iterations_per_level must be non-negative");
  const int threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();

  const int coarsest = static_cast<int>(hierarchy.levels.size()) - 1;
  std::vector<Eigen::Vector3d> q = randomTangentField(hierarchy.levels[coarsest].normals, parameters.seed);
  for (int l = coarsest; l >= 0; --l) {
    const FieldLevel& level = hierarchy.levels[l];
    for (int iteration = 0; iteration < parameters.iterations_per_level; ++iteration) {
      for (const auto& phase : level.phases) {
        const std::int64_t size = static_cast<std::int64_t>(phase.size());
        // Vertices of one phase are pairwise non-adjacent: each reads only other phases' values
        // and writes only its own, so the parallel sweep equals the serial one bit for bit.
#pragma omp parallel for num_threads(threads) schedule(static) if (size > 1024)
        for (std::int64_t p = 0; p < size; ++p)
          smoothOrientationVertex(level, q, phase[p]);
      }
    }
    if (l == 0)
      break;
    // Prolongation: copy to both children and project onto each child's tangent plane.
    const FieldLevel& finer = hierarchy.levels[l - 1];
    std::vector<Eigen::Vector3d> q_fine(finer.numVertices(), Eigen::Vector3d::Zero());
    for (std::size_t c = 0; c < level.children.size(); ++c)
      for (const std::int32_t child : level.children[c])
        if (child >= 0)
          q_fine[child] = projectToTangent(q[c], finer.normals[child]);
    q.swap(q_fine);
  }
  return q;
}

double orientationFieldEnergy(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& normals,
                              const std::vector<Eigen::Vector3d>& field)
{
  if (normals.size() != mesh.vertices.size() || field.size() != mesh.vertices.size())
    throw Error("orientation field: normals/field size does not match the mesh");
  const auto rings = computeVertexOneRings(mesh);
  double energy = 0.0;
  for (std::size_t i = 0; i < rings.size(); ++i)
    for (const std::int32_t j : rings[i]) {
      if (static_cast<std::size_t>(j) <= i)
        continue;
      const auto ab = compatOrientationExtrinsic4(field[i], normals[i], field[j], normals[j]);
      energy += 1.0 - std::abs(ab.first.dot(ab.second));
    }
  return energy;
}

std::vector<int> computeOrientationSingularityIndices(const TriangleMesh& mesh,
                                                      const std::vector<Eigen::Vector3d>& normals,
                                                      const std::vector<Eigen::Vector3d>& field)
{
  if (normals.size() != mesh.vertices.size() || field.size() != mesh.vertices.size())
    throw Error("orientation field: normals/field size does not match the mesh");
  std::vector<int> index(mesh.faces.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Face& t = mesh.faces[f];
    int sum = 0;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t i = t[k], j = t[(k + 1) % 3];
      sum += compatOrientationExtrinsicIndex4(field[i], normals[i], field[j], normals[j]);
    }
    index[f] = sum % 4;
  }
  return index;
}

int countOrientationSingularities(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& normals,
                                  const std::vector<Eigen::Vector3d>& field, std::vector<int>* singular_faces)
{
  const std::vector<int> index = computeOrientationSingularityIndices(mesh, normals, field);
  if (singular_faces)
    singular_faces->clear();
  int count = 0;
  for (std::size_t f = 0; f < index.size(); ++f)
    if (index[f] == 1 || index[f] == 3) {
      ++count;
      if (singular_faces)
        singular_faces->push_back(static_cast<int>(f));
    }
  return count;
}

}  // namespace patchdict
}  // namespace pcl
