#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/core/mesh_topology.h>

#include <algorithm>
#include <deque>
#include <numeric>
#include <set>
#include <sstream>

namespace pcl {
namespace patchdict {

namespace {

bool isDegenerate(const TriangleMesh& mesh, const Face& f)
{
  if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2])
    return true;
  const Eigen::Vector3d& a = mesh.vertices[f[0]];
  const Eigen::Vector3d& b = mesh.vertices[f[1]];
  const Eigen::Vector3d& c = mesh.vertices[f[2]];
  if (!a.allFinite() || !b.allFinite() || !c.allFinite())
    return true;
  return (b - a).cross(c - a).squaredNorm() == 0.0;
}

// Faces flagged as repeating the vertex set of an earlier face.
std::vector<char> findDuplicateFaces(const TriangleMesh& mesh)
{
  std::vector<std::pair<Face, std::int32_t>> keys(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    Face key = mesh.faces[f];
    std::sort(key.begin(), key.end());
    keys[f] = {key, static_cast<std::int32_t>(f)};
  }
  std::sort(keys.begin(), keys.end());
  std::vector<char> duplicate(mesh.faces.size(), 0);
  for (std::size_t i = 1; i < keys.size(); ++i)
    if (keys[i].first == keys[i - 1].first)
      duplicate[keys[i].second] = 1;  // sorted by index within a run: the first stays
  return duplicate;
}

void appendCount(std::ostringstream& out, std::size_t count, const char* what)
{
  if (count)
    out << ", " << count << ' ' << what;
}

}  // namespace

std::vector<int> computeVertexFanCounts(const TriangleMesh& mesh)
{
  // Around vertex v, two incident faces are in the same fan when they share an edge (v, w).
  const auto vertex_faces = computeVertexFaces(mesh);
  std::vector<int> fans(mesh.vertices.size(), 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t v = 0; v < static_cast<std::ptrdiff_t>(mesh.vertices.size()); ++v) {
    const auto& faces = vertex_faces[v];
    if (faces.empty())
      continue;
    std::vector<int> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int x) {
      while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
      return x;
    };
    // (other vertex, local face) pairs: faces listing the same other vertex share that edge.
    std::vector<std::pair<std::int32_t, int>> spokes;
    for (std::size_t i = 0; i < faces.size(); ++i)
      for (const std::int32_t w : mesh.faces[faces[i]])
        if (w != v)
          spokes.emplace_back(w, static_cast<int>(i));
    std::sort(spokes.begin(), spokes.end());
    for (std::size_t i = 1; i < spokes.size(); ++i)
      if (spokes[i].first == spokes[i - 1].first) {
        const int a = find(spokes[i].second), b = find(spokes[i - 1].second);
        if (a != b)
          parent[std::max(a, b)] = std::min(a, b);
      }
    int count = 0;
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (find(static_cast<int>(i)) == static_cast<int>(i))
        ++count;
    fans[v] = count;
  }
  return fans;
}

MeshHygieneReport inspectMesh(const TriangleMesh& mesh)
{
  MeshHygieneReport report;
  report.vertices = mesh.vertices.size();
  report.faces = mesh.faces.size();
  std::vector<char> referenced(mesh.vertices.size(), 0);
  for (const Face& f : mesh.faces)
    for (const auto v : f)
      referenced[v] = 1;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    report.unreferenced_vertices += !referenced[v];
    report.nonfinite_vertices += !mesh.vertices[v].allFinite();
  }
  for (const Face& f : mesh.faces)
    report.degenerate_faces += isDegenerate(mesh, f);
  const auto duplicate = findDuplicateFaces(mesh);
  report.duplicate_faces = static_cast<std::size_t>(std::count(duplicate.begin(), duplicate.end(), 1));

  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  for (const MeshEdge& e : adjacency.edges) {
    report.nonmanifold_edges += !e.isManifold();
    report.boundary_edges += e.isBoundary();
  }
  const auto fans = computeVertexFanCounts(mesh);
  report.nonmanifold_vertices = static_cast<std::size_t>(
      std::count_if(fans.begin(), fans.end(), [](int n) { return n > 1; }));
  report.boundary_loops = computeBoundaryLoops(mesh).size();
  std::vector<int> face_component, vertex_component;
  report.components = static_cast<std::size_t>(computeConnectedComponents(mesh, face_component, vertex_component));
  return report;
}

std::string MeshHygieneReport::summary() const
{
  std::ostringstream out;
  out << vertices << " vertices, " << faces << " faces";
  appendCount(out, unreferenced_vertices, "unreferenced vertices");
  appendCount(out, nonfinite_vertices, "non-finite vertices");
  appendCount(out, degenerate_faces, "degenerate faces");
  appendCount(out, duplicate_faces, "duplicate faces");
  appendCount(out, nonmanifold_edges, "non-manifold edges");
  appendCount(out, nonmanifold_vertices, "non-manifold vertices");
  out << ", " << boundary_loops << " boundary loops (" << boundary_edges << " edges), " << components
      << (components == 1 ? " component" : " components");
  return out.str();
}

MeshCleanupResult cleanMesh(TriangleMesh& mesh, const MeshCleanupOptions& options)
{
  MeshCleanupResult result;
  std::vector<char> drop(mesh.faces.size(), 0);
  if (options.remove_degenerate_faces)
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
      if (isDegenerate(mesh, mesh.faces[f])) {
        drop[f] = 1;
        ++result.degenerate_faces_removed;
      }
  if (options.remove_duplicate_faces) {
    // Duplicates are judged among the faces that survive the degenerate pass.
    TriangleMesh kept;
    std::vector<std::size_t> kept_index;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
      if (!drop[f]) {
        kept.faces.push_back(mesh.faces[f]);
        kept_index.push_back(f);
      }
    const auto duplicate = findDuplicateFaces(kept);
    for (std::size_t i = 0; i < duplicate.size(); ++i)
      if (duplicate[i]) {
        drop[kept_index[i]] = 1;
        ++result.duplicate_faces_removed;
      }
  }
  std::vector<Face> faces;
  faces.reserve(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    if (!drop[f])
      faces.push_back(mesh.faces[f]);
  mesh.faces.swap(faces);

  const std::size_t n = mesh.vertices.size();
  result.old_to_new.resize(n);
  std::iota(result.old_to_new.begin(), result.old_to_new.end(), 0);
  result.new_to_old = result.old_to_new;
  if (options.remove_unreferenced_vertices) {
    std::vector<char> referenced(n, 0);
    for (const Face& f : mesh.faces)
      for (const auto v : f)
        referenced[v] = 1;
    result.new_to_old.clear();
    std::vector<Eigen::Vector3d> vertices, normals;
    const bool with_normals = mesh.hasNormals();
    for (std::size_t v = 0; v < n; ++v) {
      if (!referenced[v]) {
        result.old_to_new[v] = -1;
        ++result.unreferenced_vertices_removed;
        continue;
      }
      result.old_to_new[v] = static_cast<int>(vertices.size());
      result.new_to_old.push_back(static_cast<int>(v));
      vertices.push_back(mesh.vertices[v]);
      if (with_normals)
        normals.push_back(mesh.normals[v]);
    }
    for (Face& f : mesh.faces)
      for (auto& v : f)
        v = result.old_to_new[v];
    mesh.vertices.swap(vertices);
    mesh.normals.swap(normals);
  }
  return result;
}

std::string MeshCleanupResult::summary() const
{
  std::ostringstream out;
  out << "removed " << degenerate_faces_removed << " degenerate faces, " << duplicate_faces_removed
      << " duplicate faces, " << unreferenced_vertices_removed << " unreferenced vertices";
  return out.str();
}

std::size_t orientFacesConsistently(TriangleMesh& mesh)
{
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  std::vector<char> visited(mesh.faces.size(), 0);
  std::size_t flipped = 0;
  // Whether face f traverses the edge (a, b) in that direction.
  auto runs = [&](std::int32_t f, std::int32_t a, std::int32_t b) {
    const Face& t = mesh.faces[f];
    for (int k = 0; k < 3; ++k)
      if (t[k] == a && t[(k + 1) % 3] == b)
        return true;
    return false;
  };
  for (std::size_t seed = 0; seed < mesh.faces.size(); ++seed) {
    if (visited[seed])
      continue;
    visited[seed] = 1;
    std::deque<std::int32_t> queue{static_cast<std::int32_t>(seed)};
    while (!queue.empty()) {
      const std::int32_t f = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        const std::int32_t e = adjacency.face_edges[f][k];
        if (e < 0 || adjacency.edges[e].faces.size() != 2)
          continue;  // boundary, degenerate or non-manifold: no orientation constraint
        const std::int32_t g = adjacency.edges[e].faces[0] == f ? adjacency.edges[e].faces[1]
                                                                : adjacency.edges[e].faces[0];
        if (visited[g])
          continue;
        visited[g] = 1;
        // Endpoints come from the edge, not from side k: a flipped face's sides are permuted.
        const std::int32_t a = adjacency.edges[e].v0, b = adjacency.edges[e].v1;
        if (runs(g, a, b) == runs(f, a, b)) {  // both run a→b: g disagrees with f
          std::swap(mesh.faces[g][1], mesh.faces[g][2]);
          ++flipped;
        }
        queue.push_back(g);
      }
    }
  }
  return flipped;
}

}  // namespace patchdict
}  // namespace pcl
