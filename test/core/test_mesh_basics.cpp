// Normalisation into the unit cube, vertex normals and TriangleMesh's measures (core).
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace pcl::patchdict;

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
