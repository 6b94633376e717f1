// Extraction of a quad-dominant mesh from the orientation and position fields (Jakob et al. 2015
// §6), implemented from the paper's description (§6) — not from the reference code.
#include <pcl_patchdict/quads/quad_remesher.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/quads/position_field.h>

#include "quads/field_common.h"

#include <Eigen/Geometry>

#include <boost/pending/disjoint_sets.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <limits>
#include <numeric>
#include <set>

namespace pcl {
namespace patchdict {

namespace {

// Sets of vertices on one lattice point (Boost's union-find; only the partition is used: each
// cluster is numbered by its lowest vertex, whatever element represents it).
using UnionFind = boost::disjoint_sets_with_storage<>;

/** Interior angle at corner b of the polyline a-b-c, in radians. */
double cornerAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const Eigen::Vector3d u = a - b, v = c - b;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

/** Cuts a polygon of more than four sides into quads (and one triangle for an odd count): each
  * step cuts off the four consecutive corners whose angles are closest to 90° in total. */
template <typename IsEdge>
void splitPolygon(std::vector<std::int32_t> polygon, const std::vector<Eigen::Vector3d>& p, const IsEdge& is_edge,
                  std::vector<std::vector<std::int32_t>>& faces)
{
  constexpr double kRight = 1.5707963267948966;
  while (polygon.size() > 4) {
    const std::size_t m = polygon.size();
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_start = 0;
    for (std::size_t s = 0; s < m; ++s) {
      const std::int32_t a = polygon[s], b = polygon[(s + 1) % m], c = polygon[(s + 2) % m], d = polygon[(s + 3) % m];
      if (is_edge(a, d))
        continue;  // the cut would duplicate an existing edge (a non-manifold edge)
      double score = std::abs(cornerAngle(p[d], p[a], p[b]) - kRight) +
                     std::abs(cornerAngle(p[a], p[b], p[c]) - kRight) +
                     std::abs(cornerAngle(p[b], p[c], p[d]) - kRight) +
                     std::abs(cornerAngle(p[c], p[d], p[a]) - kRight);
      if (m == 5) {
        // The triangle left over (d, e, a) must not be a sliver: penalise an obtuse corner.
        const std::int32_t e = polygon[(s + 4) % m];
        const double widest = std::max({cornerAngle(p[a], p[d], p[e]), cornerAngle(p[d], p[e], p[a]),
                                        cornerAngle(p[e], p[a], p[d])});
        score += 2.0 * std::max(0.0, widest - kRight);
      }
      if (score < best) {
        best = score;
        best_start = s;
      }
    }
    if (best == std::numeric_limits<double>::infinity())
      return;  // no admissible cut: the polygon is left open
    faces.push_back({polygon[best_start], polygon[(best_start + 1) % m], polygon[(best_start + 2) % m],
                     polygon[(best_start + 3) % m]});
    // Remove the two inner corners of the cut-off quad.
    const std::size_t r1 = (best_start + 1) % m, r2 = (best_start + 2) % m;
    std::vector<std::int32_t> rest;
    for (std::size_t k = 0; k < m; ++k)
      if (k != r1 && k != r2)
        rest.push_back(polygon[k]);
    polygon.swap(rest);
  }
  if (polygon.size() >= 3)
    faces.push_back(polygon);
}

/** Merges pairs of triangles that share an edge into quads when the quad's corners are all
  * within 45° of a right angle (the diagonals Jakob et al. delete), best pairs first. */
void mergeTrianglePairs(std::vector<std::vector<std::int32_t>>& faces, const std::vector<Eigen::Vector3d>& p)
{
  constexpr double kRight = 1.5707963267948966, kLimit = 0.7853981633974483;
  std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::size_t>> edge_faces;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t k = 0; k < faces[f].size(); ++k) {
      const std::int32_t a = faces[f][k], b = faces[f][(k + 1) % faces[f].size()];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  struct Candidate {
    double score;
    std::size_t f, g;
    std::vector<std::int32_t> quad;
  };
  std::vector<Candidate> candidates;
  for (const auto& [edge, incident] : edge_faces) {
    if (incident.size() != 2 || faces[incident[0]].size() != 3 || faces[incident[1]].size() != 3)
      continue;
    const auto& t = faces[incident[0]];
    const auto& u = faces[incident[1]];
    // t = (a, b, c) with the shared edge b→c; u then runs c→b and its third vertex d follows.
    int k = 0;
    while (!((t[k] == edge.first || t[k] == edge.second) && (t[(k + 1) % 3] == edge.first || t[(k + 1) % 3] == edge.second)))
      ++k;
    const std::int32_t b = t[k], c = t[(k + 1) % 3], a = t[(k + 2) % 3];
    std::int32_t d = -1;
    for (int j = 0; j < 3; ++j)
      if (u[j] != b && u[j] != c)
        d = u[j];
    if (d < 0 || d == a)
      continue;
    const std::vector<std::int32_t> quad{a, b, d, c};
    double worst = 0.0, total = 0.0;
    for (int j = 0; j < 4; ++j) {
      const double deviation = std::abs(cornerAngle(p[quad[(j + 3) % 4]], p[quad[j]], p[quad[(j + 1) % 4]]) - kRight);
      worst = std::max(worst, deviation);
      total += deviation;
    }
    if (worst < kLimit)
      candidates.push_back({total, incident[0], incident[1], quad});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.score < y.score; });
  std::vector<char> merged(faces.size(), 0);
  for (const Candidate& c : candidates) {
    if (merged[c.f] || merged[c.g])
      continue;
    merged[c.f] = merged[c.g] = 1;
    faces[c.f] = c.quad;
    faces[c.g].clear();
  }
  faces.erase(std::remove_if(faces.begin(), faces.end(), [](const auto& f) { return f.empty(); }), faces.end());
}

/** An edge whose two ends' origins are on the same lattice point. */
struct Collapse {
  std::int32_t i, j;
  double error;
};

/** Classifies every edge by the lattice offset between its two ends' origins: the same point
  * (a collapse) or a lattice neighbour (a link); longer and diagonal jumps are ignored. */
void classifyEdges(const FieldLevel& level, const std::vector<Eigen::Vector3d>& q, const std::vector<Eigen::Vector3d>& o,
                   double scale, std::vector<Collapse>& collapses,
                   std::vector<std::pair<std::int32_t, std::int32_t>>& links)
{
  const std::size_t n = level.numVertices();
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(n); ++i) {
    const Eigen::Vector3d& n_i = level.normals[i];
    if (n_i.squaredNorm() == 0.0)
      continue;
    for (std::int32_t e = level.adjacency_offsets[i]; e < level.adjacency_offsets[i + 1]; ++e) {
      const std::int32_t j = level.adjacency[e];
      const Eigen::Vector3d& n_j = level.normals[j];
      if (j <= i || n_j.squaredNorm() == 0.0)
        continue;
      // Turn q_j by the quarter turns that align it with q_i, so both index pairs share axes.
      const int turns = compatOrientationExtrinsicIndex4(q[i], n_i, q[j], n_j);
      Eigen::Vector3d q_j = q[j];
      for (int t = 0; t < turns; ++t)
        q_j = n_j.cross(q_j);
      double error = 0.0;
      const auto index = compatPositionExtrinsicIndex4(level.positions[i], n_i, q[i], o[i], level.positions[j], n_j,
                                                       q_j, o[j], scale, &error);
      const Eigen::Vector2i diff = (index.first - index.second).cwiseAbs();
      if (diff.maxCoeff() > 1 || (diff.x() == 1 && diff.y() == 1))
        continue;  // not lattice neighbours: a long or diagonal jump, ignored
      if (diff.sum() == 0)
        collapses.push_back({i, j, error});
      else
        links.emplace_back(i, j);
    }
  }
}

/** The output vertices: each input vertex's cluster and the clusters' weighted sums. */
struct Clusters {
  std::vector<std::int32_t> cluster;
  std::vector<Eigen::Vector3d> position_sum, normal_sum;
  std::vector<double> weight_sum;

  Eigen::Vector3d mean(std::int32_t c) const
  {
    return weight_sum[c] > 0.0 ? Eigen::Vector3d(position_sum[c] / weight_sum[c]) : position_sum[c];
  }
};

/** One cluster per set of `sets`, its position the weighted mean of its vertices' origins. */
void buildClusters(const FieldLevel& level, const std::vector<Eigen::Vector3d>& o, double scale, UnionFind& sets,
                   Clusters& clusters)
{
  const std::size_t n = level.numVertices();
  clusters.cluster.assign(n, -1);
  clusters.position_sum.clear();
  clusters.normal_sum.clear();
  clusters.weight_sum.clear();
  std::vector<std::int32_t> of_root(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (level.normals[i].squaredNorm() == 0.0)
      continue;
    const auto root = static_cast<std::int32_t>(sets.find_set(i));
    if (of_root[root] < 0) {
      of_root[root] = static_cast<std::int32_t>(clusters.position_sum.size());
      clusters.position_sum.push_back(Eigen::Vector3d::Zero());
      clusters.normal_sum.push_back(Eigen::Vector3d::Zero());
      clusters.weight_sum.push_back(0.0);
    }
    const std::int32_t c = of_root[root];
    clusters.cluster[i] = c;
    // Origins far from their vertex are less trustworthy (weights of Jakob et al.).
    const double w = std::exp(-9.0 * (o[i] - level.positions[i]).squaredNorm() / (scale * scale));
    clusters.position_sum[c] += w * o[i];
    clusters.normal_sum[c] += w * level.normals[i];
    clusters.weight_sum[c] += w;
  }
}

/** Vertices on the same lattice point become one output vertex, lowest error first; then linked
  * clusters closer than 0.3·s, one lattice point split by a broken collapse chain, are snapped
  * (Jakob et al. snap such vertices too), closest pairs first. */
Clusters clusterLatticePoints(const FieldLevel& level, const std::vector<Eigen::Vector3d>& o, double scale,
                              std::vector<Collapse>& collapses,
                              const std::vector<std::pair<std::int32_t, std::int32_t>>& links)
{
  std::stable_sort(collapses.begin(), collapses.end(),
                   [](const Collapse& a, const Collapse& b) { return a.error < b.error; });
  UnionFind sets(level.numVertices());
  for (const Collapse& c : collapses)
    sets.union_set(c.i, c.j);
  Clusters clusters;
  buildClusters(level, o, scale, sets, clusters);
  std::vector<std::pair<double, std::size_t>> close;
  for (std::size_t l = 0; l < links.size(); ++l) {
    const std::int32_t a = clusters.cluster[links[l].first], b = clusters.cluster[links[l].second];
    if (a < 0 || b < 0 || a == b)
      continue;
    const double distance = (clusters.mean(a) - clusters.mean(b)).norm();
    if (distance < 0.3 * scale)
      close.emplace_back(distance, l);
  }
  std::sort(close.begin(), close.end());
  for (const auto& [distance, l] : close)
    sets.union_set(links[l].first, links[l].second);
  if (!close.empty())
    buildClusters(level, o, scale, sets, clusters);
  return clusters;
}

using NeighbourSets = std::vector<std::set<std::int32_t>>;

/** Edges that run past another neighbour of both ends, within 0.3·s of it, skip a lattice point
  * (Jakob et al. snap such thin triangles): the path through that point replaces them. */
void removeSkippingEdges(const std::vector<Eigen::Vector3d>& positions, double scale, NeighbourSets& neighbour_sets)
{
  const std::size_t m = neighbour_sets.size();
  std::vector<std::pair<std::int32_t, std::int32_t>> spans;
  for (std::int32_t a = 0; a < static_cast<std::int32_t>(m); ++a)
    for (const std::int32_t b : neighbour_sets[a]) {
      if (b <= a)
        continue;
      const Eigen::Vector3d ab = positions[b] - positions[a];
      const double length2 = ab.squaredNorm();
      if (length2 == 0.0)
        continue;
      for (const std::int32_t c : neighbour_sets[a]) {
        if (c == b || !neighbour_sets[b].count(c))
          continue;
        const double t = (positions[c] - positions[a]).dot(ab) / length2;
        if (t <= 0.0 || t >= 1.0)
          continue;
        if ((positions[a] + t * ab - positions[c]).norm() < 0.3 * scale) {
          spans.emplace_back(a, b);
          break;
        }
      }
    }
  for (const auto& [a, b] : spans) {
    neighbour_sets[a].erase(b);
    neighbour_sets[b].erase(a);
  }
}

/** Prunes dangling vertices (degree ≤ 1) until none is left: they bound no face. */
void pruneDanglingVertices(NeighbourSets& neighbour_sets)
{
  std::vector<std::int32_t> stack;
  for (std::size_t c = 0; c < neighbour_sets.size(); ++c)
    if (neighbour_sets[c].size() == 1)
      stack.push_back(static_cast<std::int32_t>(c));
  while (!stack.empty()) {
    const std::int32_t c = stack.back();
    stack.pop_back();
    if (neighbour_sets[c].size() != 1)
      continue;
    const std::int32_t other = *neighbour_sets[c].begin();
    neighbour_sets[c].clear();
    neighbour_sets[other].erase(c);
    if (neighbour_sets[other].size() == 1)
      stack.push_back(other);
  }
}

/** Rotation system: neighbours sorted counter-clockwise about each vertex's normal, and the
  * offset of each vertex's first dart. */
void buildRotationSystem(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Vector3d>& normals,
                         const NeighbourSets& neighbour_sets, std::vector<std::vector<std::int32_t>>& neighbours,
                         std::vector<std::size_t>& dart_offset)
{
  const std::size_t m = neighbour_sets.size();
  neighbours.assign(m, {});
  dart_offset.assign(m + 1, 0);
  for (std::size_t c = 0; c < m; ++c) {
    Eigen::Vector3d e1, e2;
    detail::tangentFrame(normals[c], e1, e2);
    std::vector<std::pair<double, std::int32_t>> by_angle;
    for (const std::int32_t b : neighbour_sets[c]) {
      const Eigen::Vector3d d = positions[b] - positions[c];
      by_angle.emplace_back(std::atan2(d.dot(e2), d.dot(e1)), b);
    }
    std::sort(by_angle.begin(), by_angle.end());
    for (const auto& [angle, b] : by_angle)
      neighbours[c].push_back(b);
    dart_offset[c + 1] = dart_offset[c] + neighbours[c].size();
  }
}

/** Flags the clusters that hold a vertex of the input's boundary (or of a non-manifold edge). */
std::vector<char> boundaryClusters(const TriangleMesh& mesh, const std::vector<std::int32_t>& cluster, std::size_t m)
{
  std::vector<char> on_boundary(m, 0);
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  for (const MeshEdge& edge : adjacency.edges)
    if (!edge.isManifold() || edge.isBoundary())
      for (const std::int32_t v : {edge.v0, edge.v1})
        if (cluster[v] >= 0)
          on_boundary[cluster[v]] = 1;
  return on_boundary;
}

/** A walk that meets a vertex twice (a pinch, or an edge walked both ways) is cut into its
  * simple cycles; spurs give 2-cycles, which the caller drops. */
std::vector<std::vector<std::int32_t>> simpleCycles(const std::vector<std::int32_t>& walk)
{
  std::vector<std::vector<std::int32_t>> cycles;
  std::vector<std::int32_t> stack;
  for (const std::int32_t v : walk) {
    const auto seen_at = std::find(stack.begin(), stack.end(), v);
    if (seen_at != stack.end()) {
      cycles.emplace_back(seen_at, stack.end());
      stack.erase(seen_at + 1, stack.end());
    } else {
      stack.push_back(v);
    }
  }
  cycles.push_back(stack);
  return cycles;
}

/** Face walk: after dart a→b comes b→c with c the neighbour of b just before a (clockwise),
  * which keeps the face on the left, i.e. counter-clockwise about the normals. Faces of up to 8
  * sides are lattice defects (Jakob et al. split them); larger ones, up to 16, too when none of
  * their vertices is on the input's boundary (a hole in the lattice, not in the surface). */
std::vector<std::vector<std::int32_t>> walkFaces(const std::vector<Eigen::Vector3d>& positions,
                                                 const NeighbourSets& neighbour_sets,
                                                 const std::vector<std::vector<std::int32_t>>& neighbours,
                                                 const std::vector<std::size_t>& dart_offset,
                                                 const std::vector<char>& on_boundary)
{
  const std::size_t m = neighbours.size();
  const auto indexOf = [&](std::int32_t at, std::int32_t target) {
    const auto& ring = neighbours[at];
    return static_cast<std::size_t>(std::find(ring.begin(), ring.end(), target) - ring.begin());
  };
  const auto is_edge = [&](std::int32_t a, std::int32_t b) { return neighbour_sets[a].count(b) > 0; };
  std::vector<char> used(dart_offset[m], 0);
  std::vector<std::vector<std::int32_t>> faces;
  std::set<std::vector<std::int32_t>> seen;
  constexpr std::size_t kMaxSplitFaceSize = 8, kMaxFaceSize = 16, kMaxWalk = 64;
  for (std::size_t a0 = 0; a0 < m; ++a0) {
    for (std::size_t k0 = 0; k0 < neighbours[a0].size(); ++k0) {
      if (used[dart_offset[a0] + k0])
        continue;
      std::vector<std::int32_t> walk;
      std::int32_t a = static_cast<std::int32_t>(a0), b = neighbours[a0][k0];
      std::size_t k = k0;
      while (!used[dart_offset[a] + k]) {
        used[dart_offset[a] + k] = 1;
        if (walk.size() <= kMaxWalk)
          walk.push_back(a);
        const std::size_t back = indexOf(b, a);
        const std::size_t deg = neighbours[b].size();
        const std::size_t next = (back + deg - 1) % deg;
        a = b;
        b = neighbours[a][next];
        k = next;
      }
      if (walk.size() > kMaxWalk)
        continue;  // an open boundary or a large hole of the input
      for (const auto& polygon : simpleCycles(walk)) {
        if (polygon.size() < 3 || polygon.size() > kMaxFaceSize)
          continue;
        if (polygon.size() > kMaxSplitFaceSize &&
            std::any_of(polygon.begin(), polygon.end(), [&](std::int32_t v) { return on_boundary[v]; }))
          continue;  // a large face along the input's boundary is outside the surface
        std::vector<std::vector<std::int32_t>> pieces;
        splitPolygon(polygon, positions, is_edge, pieces);
        for (auto& piece : pieces) {
          std::vector<std::int32_t> key = piece;
          std::sort(key.begin(), key.end());
          if (seen.insert(key).second)
            faces.push_back(std::move(piece));
        }
      }
    }
  }
  return faces;
}

/** Keeps the vertices faces use, in cluster order, and renumbers the faces. */
void compactQuadMesh(const std::vector<Eigen::Vector3d>& positions, const std::vector<Eigen::Vector3d>& normals,
                     std::vector<std::vector<std::int32_t>>& faces, QuadMesh& out)
{
  const std::size_t m = positions.size();
  std::vector<std::int32_t> remap(m, -1);
  for (const auto& face : faces)
    for (const std::int32_t v : face)
      remap[v] = 0;
  for (std::size_t c = 0; c < m; ++c)
    if (remap[c] == 0) {
      remap[c] = static_cast<std::int32_t>(out.vertices.size());
      out.vertices.push_back(positions[c]);
      out.normals.push_back(normals[c]);
    }
  out.faces.reserve(faces.size());
  for (auto& face : faces) {
    for (std::int32_t& v : face)
      v = remap[v];
    out.faces.push_back(std::move(face));
  }
}

}  // namespace

void extractQuadMesh(const TriangleMesh& mesh, const FieldLevel& level, const std::vector<Eigen::Vector3d>& q,
                     const std::vector<Eigen::Vector3d>& o, double scale, QuadMesh& out)
{
  const std::size_t n = level.numVertices();
  if (q.size() != n || o.size() != n || mesh.vertices.size() != n)
    throw Error("quad extraction: field sizes do not match the mesh");
  out = QuadMesh();

  std::vector<Collapse> collapses;
  std::vector<std::pair<std::int32_t, std::int32_t>> links;
  classifyEdges(level, q, o, scale, collapses, links);
  const Clusters clusters = clusterLatticePoints(level, o, scale, collapses, links);
  const std::size_t m = clusters.position_sum.size();

  // Output edges between distinct clusters.
  NeighbourSets neighbour_sets(m);
  for (const auto& [i, j] : links) {
    const std::int32_t a = clusters.cluster[i], b = clusters.cluster[j];
    if (a != b && a >= 0 && b >= 0) {
      neighbour_sets[a].insert(b);
      neighbour_sets[b].insert(a);
    }
  }
  // Positions on the surface, normals from the cluster.
  std::vector<Eigen::Vector3d> positions(m), normals(m);
  const PointToMeshDistance surface(mesh);
  for (std::size_t c = 0; c < m; ++c) {
    positions[c] = surface.query(clusters.mean(static_cast<std::int32_t>(c))).closest_point;
    const double length = clusters.normal_sum[c].norm();
    normals[c] = length > 0.0 ? Eigen::Vector3d(clusters.normal_sum[c] / length) : Eigen::Vector3d::UnitZ();
  }
  removeSkippingEdges(positions, scale, neighbour_sets);
  pruneDanglingVertices(neighbour_sets);

  std::vector<std::vector<std::int32_t>> neighbours;
  std::vector<std::size_t> dart_offset;
  buildRotationSystem(positions, normals, neighbour_sets, neighbours, dart_offset);
  std::vector<std::vector<std::int32_t>> faces = walkFaces(
      positions, neighbour_sets, neighbours, dart_offset, boundaryClusters(mesh, clusters.cluster, m));
  mergeTrianglePairs(faces, positions);
  compactQuadMesh(positions, normals, faces, out);
}

}  // namespace patchdict
}  // namespace pcl
