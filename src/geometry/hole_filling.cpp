// HoleFilling driver: which boundary loops are holes, then per hole Liepa's triangulation and
// refinement (in parallel over holes), then one fairing solve for all new vertices.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <unordered_map>

namespace pcl {
namespace patchdict {

std::string toString(HoleFilling::SkipReason reason)
{
  switch (reason) {
  case HoleFilling::SkipReason::None: return "filled";
  case HoleFilling::SkipReason::OuterBoundary: return "outer boundary";
  case HoleFilling::SkipReason::NonManifoldVertex: return "non-manifold vertex on loop";
  case HoleFilling::SkipReason::OpenChain: return "boundary chain does not close (non-manifold edge)";
  case HoleFilling::SkipReason::TooManyEdges: return "too many edges";
  case HoleFilling::SkipReason::TooLarge: return "diameter too large";
  case HoleFilling::SkipReason::NoTriangulation: return "no triangulation without duplicate edges";
  }
  return "unknown";
}

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double loopDiameter(const TriangleMesh& mesh, const std::vector<std::int32_t>& loop)
{
  double best = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    for (std::size_t j = i + 1; j < loop.size(); ++j)
      best = std::max(best, (mesh.vertices[loop[i]] - mesh.vertices[loop[j]]).squaredNorm());
  return std::sqrt(best);
}

// The faces of the edge (a, b) in the sorted edge list of computeEdgeFaceAdjacency.
const MeshEdge* findEdge(const EdgeFaceAdjacency& adjacency, std::int32_t a, std::int32_t b)
{
  if (a > b)
    std::swap(a, b);
  const auto it = std::lower_bound(adjacency.edges.begin(), adjacency.edges.end(), std::make_pair(a, b),
                                   [](const MeshEdge& e, const std::pair<std::int32_t, std::int32_t>& key) {
                                     return std::make_pair(e.v0, e.v1) < key;
                                   });
  return it != adjacency.edges.end() && it->v0 == a && it->v1 == b ? &*it : nullptr;
}

bool faceWalks(const Face& face, std::int32_t from, std::int32_t to)
{
  for (int c = 0; c < 3; ++c)
    if (face[c] == from && face[(c + 1) % 3] == to)
      return true;
  return false;
}

// What one hole's fill needs and produces, in loop-local indices.
struct HoleWork {
  std::size_t hole = 0;  // index into Report::holes
  std::vector<std::pair<int, int>> forbidden;
  std::vector<Eigen::Vector3d> outside_apex;
  HolePatch patch;
  HoleTriangulation triangulation;
  HoleRefinementReport refinement;
};

void checkMeshForFilling(const TriangleMesh& mesh)
{
  if (mesh.faces.empty())
    throw Error("hole filling needs a mesh with faces");
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (!mesh.vertices[v].allFinite())
      throw Error("hole filling: vertex " + std::to_string(v) + " is not finite");
  for (const Face& f : mesh.faces)
    for (const std::int32_t v : f)
      if (v < 0 || static_cast<std::size_t>(v) >= mesh.vertices.size())
        throw Error("hole filling: face index " + std::to_string(v) + " is out of range");
}

/** The bounding-box diagonal of every connected component; `vertex_component` per vertex. */
std::vector<double> componentDiagonals(const TriangleMesh& mesh, std::vector<int>& vertex_component)
{
  std::vector<int> face_component;
  const int components = computeConnectedComponents(mesh, face_component, vertex_component);
  std::vector<Eigen::Vector3d> box_min(components, Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()));
  std::vector<Eigen::Vector3d> box_max(components, -box_min.front());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
    if (vertex_component[v] >= 0) {
      box_min[vertex_component[v]] = box_min[vertex_component[v]].cwiseMin(mesh.vertices[v]);
      box_max[vertex_component[v]] = box_max[vertex_component[v]].cwiseMax(mesh.vertices[v]);
    }
  std::vector<double> diagonals(static_cast<std::size_t>(components));
  for (int c = 0; c < components; ++c)
    diagonals[static_cast<std::size_t>(c)] = (box_max[c] - box_min[c]).norm();
  return diagonals;
}

/** What filling `hole` needs (it is oriented here: walked so that the mesh face across its first
  * edge walks it backwards, the fill triangles then agree with the mesh in orientation). */
HoleWork prepareHole(const TriangleMesh& mesh, const EdgeFaceAdjacency& adjacency,
                     const std::vector<std::vector<std::int32_t>>& rings, HoleFilling::Hole& hole, std::size_t index)
{
  const MeshEdge* first = findEdge(adjacency, hole.boundary[0], hole.boundary[1]);
  if (first && faceWalks(mesh.faces[first->faces.front()], hole.boundary[0], hole.boundary[1]))
    std::reverse(hole.boundary.begin() + 1, hole.boundary.end());
  HoleWork item;
  item.hole = index;
  const std::size_t n = hole.boundary.size();
  std::unordered_map<std::int32_t, int> position_in_loop;
  for (std::size_t i = 0; i < n; ++i)
    position_in_loop.emplace(hole.boundary[i], static_cast<int>(i));
  item.patch.boundary_count = n;
  item.patch.positions.resize(n);
  item.patch.scale.resize(n);
  item.outside_apex.assign(n, Eigen::Vector3d::Constant(std::nan("")));
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t a = hole.boundary[i], b = hole.boundary[(i + 1) % n];
    item.patch.positions[i] = mesh.vertices[a];
    if (const MeshEdge* edge = findEdge(adjacency, a, b))
      for (const std::int32_t w : mesh.faces[edge->faces.front()])
        if (w != a && w != b)
          item.outside_apex[i] = mesh.vertices[w];
  }
  // σ (mean length of a loop vertex's mesh edges) and the loop pairs that are mesh edges
  // already (a fill edge there would be non-manifold).
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t a = hole.boundary[i];
    double sum = 0.0;
    for (const std::int32_t u : rings[a]) {
      sum += (mesh.vertices[a] - mesh.vertices[u]).norm();
      const auto other = position_in_loop.find(u);
      if (other == position_in_loop.end())
        continue;
      const int j = other->second, gap = std::abs(j - static_cast<int>(i));
      if (j > static_cast<int>(i) && gap != 1 && gap != static_cast<int>(n) - 1)
        item.forbidden.emplace_back(static_cast<int>(i), j);
    }
    item.patch.scale[i] = rings[a].empty() ? 0.0 : sum / static_cast<double>(rings[a].size());
  }
  return item;
}

/** The input first, untouched; then each hole's new vertices and faces. Returns the new vertices;
  * holes whose triangulation failed are marked NoTriangulation, and the counts are summed. */
std::vector<std::int32_t> assembleFills(const std::vector<HoleWork>& work, TriangleMesh& filled,
                                        HoleFilling::Report& result)
{
  std::vector<std::int32_t> all_new;
  for (const HoleWork& item : work) {
    HoleFilling::Hole& hole = result.holes[item.hole];
    result.triangulation_pieces += item.triangulation.pieces;
    if (!item.triangulation.valid) {
      hole.skipped = HoleFilling::SkipReason::NoTriangulation;
      continue;
    }
    hole.max_dihedral_angle = item.triangulation.max_dihedral_angle;
    hole.refinement_rounds = item.refinement.rounds;
    const std::size_t n = item.patch.boundary_count;
    const auto first_new = static_cast<std::int32_t>(filled.vertices.size());
    const auto to_output = [&](std::int32_t local) {
      return local < static_cast<std::int32_t>(n) ? hole.boundary[local] : first_new + (local - static_cast<std::int32_t>(n));
    };
    for (std::size_t v = n; v < item.patch.positions.size(); ++v) {
      hole.new_vertices.push_back(static_cast<std::int32_t>(filled.vertices.size()));
      filled.vertices.push_back(item.patch.positions[v]);
    }
    for (const Face& f : item.patch.faces) {
      hole.new_faces.push_back(static_cast<std::int32_t>(filled.faces.size()));
      filled.faces.push_back({to_output(f[0]), to_output(f[1]), to_output(f[2])});
    }
    all_new.insert(all_new.end(), hole.new_vertices.begin(), hole.new_vertices.end());
  }
  for (const HoleFilling::Hole& hole : result.holes) {
    if (hole.filled()) {
      ++result.holes_filled;
      result.new_vertices += hole.new_vertices.size();
      result.new_faces += hole.new_faces.size();
    } else {
      ++result.holes_skipped;
    }
  }
  return all_new;
}

}  // namespace

void HoleFilling::process(TriangleMesh& out, Report* report) const
{
  if (!input_)
    throw Error("hole filling: no input mesh");
  const TriangleMesh& mesh = *input_;
  checkMeshForFilling(mesh);
  if (!(refinement_.density_factor > 0.0) || !std::isfinite(refinement_.density_factor))
    throw Error("hole filling: the density factor must be positive");
  if (!(outer_boundary_fraction_ > 0.0))
    throw Error("hole filling: the outer-boundary fraction must be positive");
  if (!(max_hole_diameter_ > 0.0))
    throw Error("hole filling: the maximum hole diameter must be positive");
  if (fairing_.continuity < 0 || fairing_.continuity > 2)
    throw Error("hole filling: fairing continuity must be 0, 1 or 2");

  Report local_report;
  Report& result = report ? *report : local_report;
  result = Report{};
  auto stage_start = Clock::now();

  // ---- which loops are holes
  const std::vector<BoundaryLoop> loops = computeBoundaryLoops(mesh);
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  const std::vector<int> fans = computeVertexFanCounts(mesh);
  const auto rings = computeVertexOneRings(mesh);
  std::vector<int> vertex_component;
  const std::vector<double> component_diagonals = componentDiagonals(mesh, vertex_component);

  std::vector<HoleWork> work;
  result.holes_found = loops.size();
  for (const BoundaryLoop& loop : loops) {
    Hole hole;
    hole.boundary = loop.vertices;
    hole.length = loop.length;
    hole.diameter = loopDiameter(mesh, loop.vertices);
    bool nonmanifold = loop.through_nonmanifold_vertex;
    for (const std::int32_t v : loop.vertices)
      nonmanifold = nonmanifold || fans[v] > 1;
    const double component_diagonal = component_diagonals[static_cast<std::size_t>(vertex_component[loop.vertices.front()])];
    if (loop.open)
      hole.skipped = SkipReason::OpenChain;
    else if (nonmanifold)
      hole.skipped = SkipReason::NonManifoldVertex;
    else if (hole.diameter >= outer_boundary_fraction_ * component_diagonal)
      hole.skipped = SkipReason::OuterBoundary;
    else if (max_hole_edges_ > 0 && loop.vertices.size() > max_hole_edges_)
      hole.skipped = SkipReason::TooManyEdges;
    else if (hole.diameter > max_hole_diameter_)
      hole.skipped = SkipReason::TooLarge;
    if (hole.filled())
      work.push_back(prepareHole(mesh, adjacency, rings, hole, result.holes.size()));
    result.holes.push_back(std::move(hole));
  }

  // ---- triangulation, per hole in parallel
  stage_start = Clock::now();
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t w = 0; w < static_cast<std::ptrdiff_t>(work.size()); ++w) {
    HoleWork& item = work[static_cast<std::size_t>(w)];
    item.triangulation = triangulateHoleLoop(item.patch.positions, item.outside_apex, item.forbidden, triangulation_);
    item.patch.faces = item.triangulation.faces;
  }
  result.seconds_triangulation = secondsSince(stage_start);

  // ---- refinement, per hole in parallel
  stage_start = Clock::now();
  if (refine_) {
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t w = 0; w < static_cast<std::ptrdiff_t>(work.size()); ++w) {
      HoleWork& item = work[static_cast<std::size_t>(w)];
      if (item.triangulation.valid)
        refineHolePatch(item.patch, item.forbidden, refinement_, &item.refinement);
    }
  }
  result.seconds_refinement = secondsSince(stage_start);

  TriangleMesh filled = mesh;
  const std::vector<std::int32_t> all_new = assembleFills(work, filled, result);

  // ---- fairing: one solve for all new vertices (holes near each other share fixed rings)
  stage_start = Clock::now();
  if (fair_ && !all_new.empty())
    result.fairing_solved = fairVertices(filled, all_new, fairing_);
  result.seconds_fairing = secondsSince(stage_start);

  if (mesh.hasNormals()) {
    const std::vector<Eigen::Vector3d> normals = computeVertexNormals(filled);
    filled.normals.resize(filled.vertices.size());
    for (std::size_t v = mesh.vertices.size(); v < filled.vertices.size(); ++v)
      filled.normals[v] = normals[v];
  } else {
    filled.normals.clear();
  }
  out = std::move(filled);
}

}  // namespace patchdict
}  // namespace pcl
