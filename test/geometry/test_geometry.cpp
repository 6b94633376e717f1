// Normalisation, vertex normals, procedural shapes and the PCL conversions of TriangleMesh.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict_eval/shapes.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <pcl/point_types.h>

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

TEST(Shapes, KnownSizesAndClosedForms)
{
  const TriangleMesh sphere = makeIcosphere(3, 1.5);
  EXPECT_EQ(sphere.faces.size(), 20u * 64u);
  for (const auto& v : sphere.vertices)
    EXPECT_NEAR(v.norm(), 1.5, 1e-14);
  EXPECT_NEAR(sphere.surfaceArea(), 4.0 * M_PI * 1.5 * 1.5, 0.05 * 4.0 * M_PI * 2.25);

  const TriangleMesh torus = makeTorus(40, 20, 1.0, 0.25);
  EXPECT_EQ(torus.vertices.size(), 800u);
  EXPECT_EQ(torus.faces.size(), 1600u);
  EXPECT_NEAR(torus.surfaceArea(), 4.0 * M_PI * M_PI * 0.25, 0.02 * 4.0 * M_PI * M_PI * 0.25);

  const TriangleMesh plane = makePlaneGrid(10, 5, 2.0, 1.0);
  EXPECT_EQ(plane.vertices.size(), 66u);
  EXPECT_NEAR(plane.surfaceArea(), 2.0, 1e-12);

  const TriangleMesh relief = makeSinusoidalRelief(32, 32, 0.05, 0.25);
  for (const auto& v : relief.vertices)
    EXPECT_DOUBLE_EQ(v.z(), sinusoidalReliefHeight(v.x(), v.y(), 0.05, 0.25));
}

TEST(TriangleMeshBasics, MeanEdgeLengthOfAUnitGrid)
{
  // 2×2 cells of side 1: 12 axis edges of length 1 and 4 diagonals of length √2.
  const TriangleMesh grid = makePlaneGrid(2, 2, 2.0, 2.0);
  EXPECT_NEAR(grid.meanEdgeLength(), (12.0 + 4.0 * std::sqrt(2.0)) / 16.0, 1e-15);
  EXPECT_NEAR(grid.boundingBoxDiagonal(), std::sqrt(8.0), 1e-15);
}

TEST(TriangleMeshConversions, PolygonMeshRoundTrip)
{
  TriangleMesh mesh = makeTorus(8, 6);
  for (auto& v : mesh.vertices)  // float-representable, as PolygonMesh stores float32
    v = v.cast<float>().cast<double>();
  mesh.normals.assign(mesh.vertices.size(), Eigen::Vector3d(0, 0, 1));
  pcl::PolygonMesh polygon_mesh;
  toPolygonMesh(mesh, polygon_mesh);
  EXPECT_EQ(polygon_mesh.polygons.size(), mesh.faces.size());
  TriangleMesh back;
  fromPolygonMesh(polygon_mesh, back);
  EXPECT_EQ(back.vertices, mesh.vertices);
  EXPECT_EQ(back.faces, mesh.faces);
  EXPECT_EQ(back.normals, mesh.normals);
}

TEST(TriangleMeshConversions, PolygonMeshQuadsAreTriangulatedAndBadIndicesRejected)
{
  TriangleMesh square = makePlaneGrid(1, 1);
  pcl::PolygonMesh polygon_mesh;
  toPolygonMesh(square, polygon_mesh);
  polygon_mesh.polygons.resize(1);
  polygon_mesh.polygons[0].vertices = {0, 1, 3, 2};
  TriangleMesh back;
  fromPolygonMesh(polygon_mesh, back);
  ASSERT_EQ(back.faces.size(), 2u);
  EXPECT_EQ(back.faces[1], (Face{0, 3, 2}));
  polygon_mesh.polygons[0].vertices = {0, 1, 4};
  EXPECT_THROW(fromPolygonMesh(polygon_mesh, back), Error);
}

TEST(TriangleMeshConversions, PointCloudRoundTripDropsNonFinitePoints)
{
  pcl::PointCloud<pcl::PointNormal> cloud;
  for (int i = 0; i < 5; ++i) {
    pcl::PointNormal p;
    p.x = static_cast<float>(i);
    p.y = 2.f * static_cast<float>(i);
    p.z = -1.f;
    p.normal_x = 0.f;
    p.normal_y = 0.f;
    p.normal_z = 1.f;
    cloud.push_back(p);
  }
  cloud[2].x = std::numeric_limits<float>::quiet_NaN();
  TriangleMesh mesh;
  std::vector<int> index_map;
  fromPointCloud(cloud, mesh, &index_map);
  EXPECT_EQ(mesh.vertices.size(), 4u);
  EXPECT_EQ(index_map, (std::vector<int>{0, 1, 3, 4}));
  EXPECT_TRUE(mesh.hasNormals());
  EXPECT_EQ(mesh.vertices[2], Eigen::Vector3d(3, 6, -1));
  pcl::PointCloud<pcl::PointXYZ> xyz;
  toPointCloud(mesh, xyz);
  ASSERT_EQ(xyz.size(), 4u);
  EXPECT_EQ(xyz[3].y, 8.f);
}
