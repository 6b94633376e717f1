// The PCL bridge: the core's frames (rows X, Y, Z in double) and pcl::ReferenceFrame — the float rounding is
// bit for bit the round trip through PCL's float axes, and the conversions of whole lists agree.
#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/pcl/reference_frame.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict_eval/shapes.h>

#include <gtest/gtest.h>

#include <limits>

#include <cmath>

#include <Eigen/Geometry>

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

using namespace pcl::patchdict;

namespace {

bool sameBits(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b)
{
  return std::memcmp(a.data(), b.data(), sizeof(double) * 9) == 0;
}

/** Rows X, Y, Z of a uniformly random rotation (normalised Gaussian quaternion). */
Eigen::Matrix3d randomRotation(std::mt19937_64& random)
{
  std::normal_distribution<double> gaussian;
  Eigen::Quaterniond q(gaussian(random), gaussian(random), gaussian(random), gaussian(random));
  q.normalize();
  return q.toRotationMatrix().transpose();
}

}  // namespace

TEST(LocalFrame, RoundingIsTheRoundTripThroughReferenceFrameBitForBit)
{
  std::mt19937_64 random(26);
  for (int i = 0; i < 100000; ++i) {
    const Eigen::Matrix3d rows = randomRotation(random);
    const Eigen::Matrix3d rounded = roundToSinglePrecision(rows);
    ASSERT_TRUE(sameBits(rounded, fromReferenceFrame(toReferenceFrame(rows)))) << "rotation " << i;
    ASSERT_TRUE(sameBits(roundToSinglePrecision(rounded), rounded)) << "rounding twice, rotation " << i;
    ASSERT_LT((rounded - rows).cwiseAbs().maxCoeff(), 1e-7);
  }
  // Entries on the way to float's edges (signed zeros, subnormals, ties) and a non-rotation.
  Eigen::Matrix3d odd;
  odd << 0.0, -0.0, 1e-40, -1e-46, 1.0 + 0x1p-24, 1.0 + 0x1p-23 + 0x1p-24, 3e38, -0.1, 1.0 / 3.0;
  EXPECT_TRUE(sameBits(roundToSinglePrecision(odd), fromReferenceFrame(toReferenceFrame(odd))));
}

TEST(LocalFrame, ListsConvertToAndFromACloudOfReferenceFrames)
{
  std::mt19937_64 random(3);
  std::vector<Eigen::Matrix3d> frames;
  for (int i = 0; i < 50; ++i)
    frames.push_back(roundToSinglePrecision(randomRotation(random)));
  const pcl::PointCloud<pcl::ReferenceFrame> cloud = toReferenceFrames(frames);
  ASSERT_EQ(cloud.size(), frames.size());
  EXPECT_EQ(cloud.width, static_cast<std::uint32_t>(frames.size()));
  EXPECT_EQ(cloud.height, 1u);
  const std::vector<Eigen::Matrix3d> back = fromReferenceFrames(cloud);
  ASSERT_EQ(back.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_TRUE(sameBits(back[i], frames[i]));  // rounded frames survive the float type exactly
    EXPECT_EQ(cloud[i].x_axis[1], static_cast<float>(frames[i](0, 1)));
    EXPECT_EQ(cloud[i].z_axis[2], static_cast<float>(frames[i](2, 2)));
  }
  EXPECT_TRUE(toReferenceFrames({}).empty());
}

// The PCL conversions of TriangleMesh: pcl::PolygonMesh and pcl::PointCloud round trips.

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
