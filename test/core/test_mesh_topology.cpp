#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <algorithm>

using namespace pcl::patchdict;

namespace {

// A 3×3 grid with its centre quad removed: one outer loop (12 edges) and one hole (4 edges).
TriangleMesh gridWithHole()
{
  TriangleMesh mesh = makePlaneGrid(3, 3);
  // Faces 8 and 9 are the two triangles of quad (1, 1).
  mesh.faces.erase(mesh.faces.begin() + 8, mesh.faces.begin() + 10);
  return mesh;
}

}  // namespace

TEST(MeshTopology, ClosedSurfaceHasNoBoundaryAndEulerCharacteristicTwo)
{
  const TriangleMesh sphere = makeIcosphere(2);
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(sphere);
  EXPECT_EQ(adjacency.edges.size(), 480u);  // 320 faces × 3 / 2
  const long euler = static_cast<long>(sphere.vertices.size()) - static_cast<long>(adjacency.edges.size()) +
                     static_cast<long>(sphere.faces.size());
  EXPECT_EQ(euler, 2);
  for (const MeshEdge& e : adjacency.edges)
    EXPECT_EQ(e.faces.size(), 2u);
  EXPECT_TRUE(computeBoundaryLoops(sphere).empty());
}

TEST(MeshTopology, TorusHasEulerCharacteristicZero)
{
  const TriangleMesh torus = makeTorus(12, 8);
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(torus);
  EXPECT_EQ(static_cast<long>(torus.vertices.size()) - static_cast<long>(adjacency.edges.size()) +
                static_cast<long>(torus.faces.size()),
            0);
}

TEST(MeshTopology, FaceEdgesPointBackToTheirFace)
{
  const TriangleMesh mesh = gridWithHole();
  const EdgeFaceAdjacency adjacency = computeEdgeFaceAdjacency(mesh);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const MeshEdge& e = adjacency.edges[adjacency.face_edges[f][k]];
      const auto a = std::min(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]);
      const auto b = std::max(mesh.faces[f][k], mesh.faces[f][(k + 1) % 3]);
      EXPECT_EQ(e.v0, a);
      EXPECT_EQ(e.v1, b);
      EXPECT_NE(std::find(e.faces.begin(), e.faces.end(), static_cast<std::int32_t>(f)), e.faces.end());
    }
}

TEST(MeshTopology, OneRingsOfAGrid)
{
  const TriangleMesh grid = makePlaneGrid(2, 2);  // vertices 0..8, row-major 3×3
  const auto rings = computeVertexOneRings(grid);
  ASSERT_EQ(rings.size(), 9u);
  // The centre vertex 4: with the (a, b, c), (a, c, d) split it has 6 neighbours.
  EXPECT_EQ(rings[4], (std::vector<std::int32_t>{0, 1, 3, 5, 7, 8}));
  EXPECT_EQ(rings[0], (std::vector<std::int32_t>{1, 3, 4}));
  EXPECT_EQ(rings[2], (std::vector<std::int32_t>{1, 5}));
}

TEST(MeshTopology, BoundaryLoopsOfAGridWithAHole)
{
  const TriangleMesh mesh = gridWithHole();
  const auto loops = computeBoundaryLoops(mesh);
  ASSERT_EQ(loops.size(), 2u);
  EXPECT_EQ(loops[0].vertices.size(), 12u);  // outer, the longest, comes first
  EXPECT_NEAR(loops[0].length, 4.0, 1e-12);
  EXPECT_EQ(loops[1].vertices.size(), 4u);
  EXPECT_NEAR(loops[1].length, 4.0 / 3.0, 1e-12);
  std::vector<std::int32_t> hole = loops[1].vertices;
  std::sort(hole.begin(), hole.end());
  EXPECT_EQ(hole, (std::vector<std::int32_t>{5, 6, 9, 10}));
  for (const auto& loop : loops) {
    EXPECT_FALSE(loop.open);
    EXPECT_FALSE(loop.through_nonmanifold_vertex);
  }
}

TEST(MeshTopology, LoopThroughABowtieVertexIsFlagged)
{
  // Two triangles sharing only vertex 0.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  mesh.faces = {{0, 1, 2}, {0, 3, 4}};
  const auto loops = computeBoundaryLoops(mesh);
  ASSERT_FALSE(loops.empty());
  bool flagged = false;
  for (const auto& loop : loops)
    flagged = flagged || loop.through_nonmanifold_vertex;
  EXPECT_TRUE(flagged);
}

TEST(MeshTopology, FlaggedFaceRegionsJoinThroughEdgesOnly)
{
  // Flag the faces whose centroid lies in two separate squares of a grid; a vertex contact is
  // not a connection (two faces meeting at a corner stay apart).
  const TriangleMesh grid = makePlaneGrid(10, 10);
  std::vector<char> flagged(grid.faces.size(), 0);
  std::size_t in_a = 0, in_b = 0;
  for (std::size_t f = 0; f < grid.faces.size(); ++f) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      c += grid.vertices[static_cast<std::size_t>(grid.faces[f][k])] / 3.0;
    const bool a = c.x() < 0.3 && c.y() < 0.3, b = c.x() > 0.6 && c.y() > 0.6;
    flagged[f] = (a || b) ? 1 : 0;
    in_a += a ? 1 : 0;
    in_b += b ? 1 : 0;
  }
  const auto regions = flaggedFaceRegions(grid, flagged);
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0].size(), in_a);
  EXPECT_EQ(regions[1].size(), in_b);
  EXPECT_TRUE(std::is_sorted(regions[0].begin(), regions[0].end()));
  std::vector<char> corner(grid.faces.size(), 0);
  corner[0] = 1;  // two faces sharing only a vertex: the first square's lower triangle and the next row's
  const Face& first = grid.faces[0];
  for (std::size_t f = 1; f < grid.faces.size(); ++f) {
    int shared = 0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        shared += grid.faces[f][i] == first[j] ? 1 : 0;
    if (shared == 1) {
      corner[f] = 1;
      break;
    }
  }
  EXPECT_EQ(flaggedFaceRegions(grid, corner).size(), 2u);
  EXPECT_THROW(flaggedFaceRegions(grid, std::vector<char>(3, 1)), Error);
}

TEST(MeshTopology, ConnectedComponents)
{
  TriangleMesh mesh = makePlaneGrid(2, 2);
  const TriangleMesh other = makeIcosphere(0);
  const auto offset = static_cast<std::int32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (Face f : other.faces) {
    for (auto& v : f)
      v += offset;
    mesh.faces.push_back(f);
  }
  mesh.vertices.emplace_back(9, 9, 9);  // isolated
  std::vector<int> face_component, vertex_component;
  EXPECT_EQ(computeConnectedComponents(mesh, face_component, vertex_component), 2);
  EXPECT_EQ(face_component.front(), 0);
  EXPECT_EQ(face_component.back(), 1);
  EXPECT_EQ(vertex_component.back(), -1);
  EXPECT_EQ(vertex_component[0], 0);
  EXPECT_EQ(vertex_component[offset], 1);
}
