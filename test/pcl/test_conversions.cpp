// The PCL conversions of TriangleMesh: pcl::PolygonMesh and pcl::PointCloud round trips.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict_eval/shapes.h>

#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

using namespace pcl::patchdict;

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
