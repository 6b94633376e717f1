#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>

#include <algorithm>
#include <numeric>
#include <tuple>

namespace pcl {
namespace patchdict {

namespace {

// Union-find with path halving; used for components.
struct DisjointSets {
  std::vector<int> parent;
  explicit DisjointSets(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x)
  {
    while (parent[x] != x)
      x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b)
  {
    a = find(a);
    b = find(b);
    if (a != b)
      parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

EdgeFaceAdjacency computeEdgeFaceAdjacency(const TriangleMesh& mesh)
{
  // Sort (edge key, face, side) records so that equal edges become runs: O(F log F), no hashing.
  // The key packs the edge's two (non-negative) vertex indices, smaller first, into 64 bits; the
  // second word is 3 × face + side, so each run lists its faces in increasing order.
  struct Side {
    std::uint64_t key;
    std::uint64_t face_side;
    bool operator<(const Side& other) const
    {
      return key < other.key || (key == other.key && face_side < other.face_side);
    }
  };
  std::vector<Side> sides;
  sides.reserve(mesh.faces.size() * 3);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Face& t = mesh.faces[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      continue;  // a face repeating a vertex has no proper edges; it would fake non-manifold ones
    for (int k = 0; k < 3; ++k) {
      std::int32_t a = t[k], b = t[(k + 1) % 3];
      if (a > b)
        std::swap(a, b);
      sides.push_back({(static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b),
                       3 * static_cast<std::uint64_t>(f) + static_cast<std::uint64_t>(k)});
    }
  }
  std::sort(sides.begin(), sides.end());
  EdgeFaceAdjacency adjacency;
  adjacency.face_edges.assign(mesh.faces.size(), {-1, -1, -1});
  std::size_t edge_count = 0;
  for (std::size_t i = 0; i < sides.size(); ++i)
    edge_count += i == 0 || sides[i].key != sides[i - 1].key;
  adjacency.edges.reserve(edge_count);
  for (std::size_t i = 0; i < sides.size();) {
    MeshEdge edge;
    edge.v0 = static_cast<std::int32_t>(sides[i].key >> 32);
    edge.v1 = static_cast<std::int32_t>(sides[i].key & 0xffffffffu);
    const auto edge_index = static_cast<std::int32_t>(adjacency.edges.size());
    std::size_t j = i;
    while (j < sides.size() && sides[j].key == sides[i].key)
      ++j;
    edge.faces.reserve(j - i);
    for (std::size_t s = i; s < j; ++s) {
      const auto face = static_cast<std::int32_t>(sides[s].face_side / 3);
      edge.faces.push_back(face);
      adjacency.face_edges[static_cast<std::size_t>(face)][sides[s].face_side % 3] = edge_index;
    }
    adjacency.edges.push_back(std::move(edge));
    i = j;
  }
  return adjacency;
}

std::vector<std::vector<std::int32_t>> computeSmoothingNeighbours(const TriangleMesh& mesh)
{
  const std::size_t n = mesh.vertices.size();
  std::vector<std::vector<std::int32_t>> ring(n), boundary_ring(n);
  for (const MeshEdge& e : computeEdgeFaceAdjacency(mesh).edges) {
    ring[static_cast<std::size_t>(e.v0)].push_back(e.v1);
    ring[static_cast<std::size_t>(e.v1)].push_back(e.v0);
    if (!e.isManifold() || e.isBoundary()) {
      boundary_ring[static_cast<std::size_t>(e.v0)].push_back(e.v1);
      boundary_ring[static_cast<std::size_t>(e.v1)].push_back(e.v0);
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (!boundary_ring[v].empty())
      ring[v] = std::move(boundary_ring[v]);
  return ring;
}

std::vector<std::vector<std::int32_t>> computeVertexOneRings(const TriangleMesh& mesh)
{
  std::vector<std::vector<std::int32_t>> rings(mesh.vertices.size());
  for (const Face& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t a = f[k], b = f[(k + 1) % 3];
      if (a == b)
        continue;
      rings[a].push_back(b);
      rings[b].push_back(a);
    }
  for (auto& ring : rings) {
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
  }
  return rings;
}

std::vector<std::vector<std::int32_t>> computeVertexFaces(const TriangleMesh& mesh)
{
  std::vector<std::vector<std::int32_t>> vertex_faces(mesh.vertices.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      auto& list = vertex_faces[mesh.faces[f][k]];
      if (list.empty() || list.back() != static_cast<std::int32_t>(f))
        list.push_back(static_cast<std::int32_t>(f));
    }
  return vertex_faces;
}

std::vector<BoundaryLoop> computeBoundaryLoops(const TriangleMesh& mesh)
{
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  // Boundary edges around each vertex.
  std::vector<std::vector<std::int32_t>> incident(mesh.vertices.size());
  std::vector<std::int32_t> boundary_edges;
  for (std::size_t e = 0; e < adjacency.edges.size(); ++e)
    if (adjacency.edges[e].isBoundary()) {
      boundary_edges.push_back(static_cast<std::int32_t>(e));
      incident[adjacency.edges[e].v0].push_back(static_cast<std::int32_t>(e));
      incident[adjacency.edges[e].v1].push_back(static_cast<std::int32_t>(e));
    }
  std::vector<char> used(adjacency.edges.size(), 0);
  std::vector<BoundaryLoop> loops;
  for (const std::int32_t start_edge : boundary_edges) {
    if (used[start_edge])
      continue;
    BoundaryLoop loop;
    const MeshEdge& first = adjacency.edges[start_edge];
    const std::int32_t start = first.v0;
    std::int32_t current = first.v1;
    used[start_edge] = 1;
    loop.vertices.push_back(start);
    loop.length += (mesh.vertices[first.v0] - mesh.vertices[first.v1]).norm();
    if (incident[start].size() > 2)
      loop.through_nonmanifold_vertex = true;
    while (current != start) {
      loop.vertices.push_back(current);
      if (incident[current].size() > 2)
        loop.through_nonmanifold_vertex = true;
      // Next unused boundary edge at `current`, lowest index first for determinism.
      std::int32_t next_edge = -1;
      for (const std::int32_t candidate : incident[current])
        if (!used[candidate]) {
          next_edge = candidate;
          break;
        }
      if (next_edge < 0) {
        loop.open = true;
        break;
      }
      used[next_edge] = 1;
      const MeshEdge& e = adjacency.edges[next_edge];
      const std::int32_t next = e.v0 == current ? e.v1 : e.v0;
      loop.length += (mesh.vertices[current] - mesh.vertices[next]).norm();
      current = next;
    }
    loops.push_back(std::move(loop));
  }
  std::stable_sort(loops.begin(), loops.end(), [](const BoundaryLoop& a, const BoundaryLoop& b) {
    if (a.length != b.length)
      return a.length > b.length;
    return *std::min_element(a.vertices.begin(), a.vertices.end()) <
           *std::min_element(b.vertices.begin(), b.vertices.end());
  });
  return loops;
}

int computeConnectedComponents(const TriangleMesh& mesh, std::vector<int>& face_component,
                               std::vector<int>& vertex_component)
{
  DisjointSets sets(mesh.vertices.size());
  for (const Face& f : mesh.faces) {
    sets.unite(f[0], f[1]);
    sets.unite(f[1], f[2]);
  }
  // Number the components in order of their first face.
  std::vector<int> label(mesh.vertices.size(), -1);
  int count = 0;
  face_component.assign(mesh.faces.size(), -1);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const int root = sets.find(mesh.faces[f][0]);
    if (label[root] < 0)
      label[root] = count++;
    face_component[f] = label[root];
  }
  vertex_component.assign(mesh.vertices.size(), -1);
  for (const Face& f : mesh.faces)
    for (int k = 0; k < 3; ++k)
      vertex_component[f[k]] = label[sets.find(f[k])];
  return count;
}

std::vector<std::vector<std::int32_t>> flaggedFaceRegions(const TriangleMesh& mesh, const std::vector<char>& flagged)
{
  if (flagged.size() != mesh.faces.size())
    throw Error("flagged face regions: one flag per face is needed");
  // Union-find over the edges whose faces are both flagged; the root of a region is its smallest face.
  std::vector<std::int32_t> parent(mesh.faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  const auto find = [&](std::int32_t x) {
    while (parent[static_cast<std::size_t>(x)] != x)
      x = parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    return x;
  };
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  for (const MeshEdge& edge : adjacency.edges)
    for (std::size_t i = 0; i + 1 < edge.faces.size(); ++i) {
      const std::int32_t a = edge.faces[i], b = edge.faces[i + 1];
      if (flagged[static_cast<std::size_t>(a)] && flagged[static_cast<std::size_t>(b)]) {
        const std::int32_t ra = find(a), rb = find(b);
        if (ra != rb)
          parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
      }
    }
  std::vector<std::int32_t> region_of(mesh.faces.size(), -1);
  std::vector<std::vector<std::int32_t>> regions;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!flagged[f])
      continue;
    const auto root = static_cast<std::size_t>(find(static_cast<std::int32_t>(f)));
    if (region_of[root] < 0) {
      region_of[root] = static_cast<std::int32_t>(regions.size());
      regions.emplace_back();
    }
    regions[static_cast<std::size_t>(region_of[root])].push_back(static_cast<std::int32_t>(f));
  }
  return regions;
}

}  // namespace patchdict
}  // namespace pcl
