// The core mesh: topology (edges, 1-rings, boundary loops, components), normalisation into the unit
// cube, vertex normals and TriangleMesh's measures.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <gtest/gtest.h>

#include <random>

#include <limits>

#include <cmath>

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

// Normalisation into the unit cube, vertex normals and TriangleMesh's measures.

TEST(Normalization, LargestSideBecomesOneCentredAtTheOrigin)
{
  TriangleMesh mesh = makePlaneGrid(4, 4, 3.0, 2.0);
  for (auto& v : mesh.vertices)
    v += Eigen::Vector3d(10, -5, 7);
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(mesh);
  EXPECT_DOUBLE_EQ(normalization.scale, 1.0 / 3.0);
  EXPECT_TRUE(normalization.center.isApprox(Eigen::Vector3d(11.5, -4.0, 7.0)));
  normalization.apply(mesh);
  Eigen::Vector3d lo, hi;
  mesh.boundingBox(lo, hi);
  EXPECT_NEAR(hi.x() - lo.x(), 1.0, 1e-15);
  EXPECT_NEAR(hi.y() - lo.y(), 2.0 / 3.0, 1e-15);
  EXPECT_NEAR((lo + hi).norm(), 0.0, 1e-15);
  EXPECT_NEAR(normalization.applyLength(0.3), 0.1, 1e-15);
  EXPECT_NEAR(normalization.invertLength(0.1), 0.3, 1e-15);
}

TEST(Normalization, InverseRestoresFloatDataBitExactly)
{
  // Float32 data (as in every scan file) survives normalise → invert → float exactly.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> coordinate(-1234.5f, 987.25f);
  TriangleMesh mesh;
  for (int i = 0; i < 10000; ++i)
    mesh.vertices.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
  const TriangleMesh original = mesh;
  const UnitCubeNormalization normalization = UnitCubeNormalization::fromMesh(mesh);
  normalization.apply(mesh);
  normalization.invert(mesh);
  double worst = 0.0;
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    worst = std::max(worst, (mesh.vertices[i] - original.vertices[i]).cwiseAbs().maxCoeff());
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(static_cast<float>(mesh.vertices[i][k]), static_cast<float>(original.vertices[i][k]));
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(Normalization, RejectsDegenerateInput)
{
  TriangleMesh empty;
  EXPECT_THROW(UnitCubeNormalization::fromMesh(empty), Error);
  TriangleMesh point;
  point.vertices = {{1, 2, 3}, {1, 2, 3}};
  EXPECT_THROW(UnitCubeNormalization::fromMesh(point), Error);
  TriangleMesh nan_mesh;
  nan_mesh.vertices = {{0, 0, 0}, {std::numeric_limits<double>::quiet_NaN(), 1, 1}};
  EXPECT_THROW(UnitCubeNormalization::fromMesh(nan_mesh), Error);
  TriangleMesh huge;
  huge.vertices = {{-1e308, 0, 0}, {1e308, 0, 0}};  // side overflows to +inf
  EXPECT_THROW(UnitCubeNormalization::fromMesh(huge), Error);
}

TEST(VertexNormals, SphereNormalsAreRadial)
{
  const TriangleMesh sphere = makeIcosphere(3, 2.0);
  const auto normals = computeVertexNormals(sphere);
  double worst = 0.0;
  for (std::size_t v = 0; v < sphere.vertices.size(); ++v)
    worst = std::max(worst, (normals[v] - sphere.vertices[v].normalized()).norm());
  EXPECT_LT(worst, 1e-2);  // the icosphere's tessellation error at level 3
}

TEST(VertexNormals, AngleWeightingIgnoresTheTriangulation)
{
  // A cube corner whose z = 0 side is split into two triangles at the corner: angle weighting
  // still gives the symmetric (1,1,1)/√3, where weighting by face count would tilt it to (1,1,2).
  TriangleMesh corner;
  corner.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}};
  corner.faces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}};
  const auto normals = computeVertexNormals(corner);
  EXPECT_NEAR((normals[0] - Eigen::Vector3d(1, 1, 1).normalized()).norm(), 0.0, 1e-15);
  for (const auto& n : computeVertexNormals(makePlaneGrid(3, 3)))
    EXPECT_NEAR((n - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-15);
}

TEST(TriangleMeshBasics, MeanEdgeLengthOfAUnitGrid)
{
  // 2×2 cells of side 1: 12 axis edges of length 1 and 4 diagonals of length √2.
  const TriangleMesh grid = makePlaneGrid(2, 2, 2.0, 2.0);
  EXPECT_NEAR(grid.meanEdgeLength(), (12.0 + 4.0 * std::sqrt(2.0)) / 16.0, 1e-15);
  EXPECT_NEAR(grid.boundingBoxDiagonal(), std::sqrt(8.0), 1e-15);
}
