// QuadFrameEstimation, the PCL class: on a sampled sphere (three point types, the cloud's own
// normals where the type has them) the frames are orthonormal, their Z the sphere's normal, the
// seeds on the sphere; setIndices is honoured; on the bundled bunny as a pcl::PolygonMesh the seeds
// lie on the mesh and Z follows its normals; misuse is an Error.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict/pcl/quad_frame_estimation.h>
#include <pcl_patchdict/pcl/reference_frame.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <pcl/type_traits.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

using namespace pcl::patchdict;

namespace {

constexpr double kDegree = 3.14159265358979323846 / 180.0;
const Eigen::Vector3d kCentre(1.0, -2.0, 0.5);
constexpr double kRadius = 2.0;

/** 12 000 uniform random points of the sphere |p − c| = 2, with outward normals when PointT has them. */
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr sphereCloud()
{
  std::mt19937_64 random(11);
  std::normal_distribution<double> gaussian;
  typename pcl::PointCloud<PointT>::Ptr cloud(new pcl::PointCloud<PointT>);
  for (int i = 0; i < 12000; ++i) {
    const Eigen::Vector3d n = Eigen::Vector3d(gaussian(random), gaussian(random), gaussian(random)).normalized();
    PointT p;
    p.getVector3fMap() = (kCentre + kRadius * n).cast<float>();
    if constexpr (pcl::traits::has_normal_v<PointT>)
      p.getNormalVector3fMap() = n.cast<float>();
    cloud->push_back(p);
  }
  return cloud;
}

/** Largest deviation of R·Rᵀ from the identity, and whether every frame is right-handed. */
double orthonormality(const pcl::PointCloud<pcl::ReferenceFrame>& frames, bool& right_handed)
{
  double worst = 0.0;
  right_handed = true;
  for (const auto& frame : frames) {
    const Eigen::Matrix3d r = fromReferenceFrame(frame);
    worst = std::max(worst, (r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff());
    right_handed = right_handed && r.determinant() > 0.0;
  }
  return worst;
}

}  // namespace

template <typename PointT>
class PclQuadFrames : public ::testing::Test {};
using PointTypes = ::testing::Types<pcl::PointXYZ, pcl::PointNormal, pcl::PointXYZRGBNormal>;
TYPED_TEST_SUITE(PclQuadFrames, PointTypes);

TYPED_TEST(PclQuadFrames, OnASampledSphereFramesAreOrthonormalRadialAndSeedsOnTheSphere)
{
  QuadFrameEstimation<TypeParam> estimation;
  estimation.setInputCloud(sphereCloud<TypeParam>());
  pcl::PointCloud<pcl::PointNormal> seeds;
  pcl::PointCloud<pcl::ReferenceFrame> frames;
  estimation.compute(seeds, frames);
  const QuadFrameReport& report = estimation.getReport();
  EXPECT_TRUE(report.from_cloud);
  EXPECT_EQ(report.normals_given, pcl::traits::has_normal_v<TypeParam>);
  EXPECT_NEAR(report.quad_length, 0.03 * 2.0 * kRadius, 0.01 * 0.03 * 2.0 * kRadius);  // automatic: 0.03 × 4
  // The sphere's area over L², 1 + 4 seeds per quad: 50.3 / 0.0144 · 5 ≈ 17 500.
  ASSERT_EQ(seeds.size(), frames.size());
  EXPECT_GT(seeds.size(), 12000u);
  EXPECT_LT(seeds.size(), 24000u);
  bool right_handed = false;
  EXPECT_LT(orthonormality(frames, right_handed), 1e-5);
  EXPECT_TRUE(right_handed);
  std::size_t radial = 0;
  double farthest = 0.0;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const Eigen::Vector3d p = seeds[s].getVector3fMap().cast<double>();
    const Eigen::Vector3d truth = (p - kCentre).normalized();
    const Eigen::Vector3d z = fromReferenceFrame(frames[s]).row(2).transpose();
    EXPECT_EQ(seeds[s].getNormalVector3fMap(), z.cast<float>());  // the seed's normal is its frame's Z
    radial += std::acos(std::clamp(z.dot(truth), -1.0, 1.0)) < 10.0 * kDegree;
    farthest = std::max(farthest, std::abs((p - kCentre).norm() - kRadius));
  }
  EXPECT_GE(static_cast<double>(radial) / static_cast<double>(seeds.size()), 0.97);
  // Seeds lie on the smoothed Poisson surface of the samples: within 1 % of the radius.
  EXPECT_LT(farthest, 0.01 * kRadius);
  pcl::PolygonMesh quads, coarse;
  estimation.getQuadMesh(quads);
  estimation.getCoarseMesh(coarse);
  EXPECT_EQ(quads.polygons.size(), report.quad_faces);
  EXPECT_GT(report.quads, 9 * report.quad_faces / 10);
  EXPECT_EQ(coarse.polygons.size(), report.coarse_faces);
  EXPECT_EQ(estimation.getSeedQuads().size(), seeds.size());
}

TEST(PclQuadFrames, IndicesAreHonouredAndLIsInTheInputsUnits)
{
  // Only the upper half of the sphere, by indices: no seed below its rim.
  const auto cloud = sphereCloud<pcl::PointXYZ>();
  pcl::IndicesPtr upper(new pcl::Indices);
  for (std::size_t i = 0; i < cloud->size(); ++i)
    if ((*cloud)[i].z > kCentre.z())
      upper->push_back(static_cast<int>(i));
  QuadFrameEstimation<pcl::PointXYZ> estimation;
  estimation.setInputCloud(cloud);
  estimation.setIndices(upper);
  estimation.setQuadLength(0.25);
  estimation.setOverlap(0);
  pcl::PointCloud<pcl::PointNormal> seeds;
  pcl::PointCloud<pcl::ReferenceFrame> frames;
  estimation.compute(seeds, frames);
  const QuadFrameReport& report = estimation.getReport();
  std::printf("half sphere: %zu surface faces, %zu quad faces (%zu quads), %zu seeds (%zu coverage)\n",
              report.surface_faces, report.quad_faces, report.quads, report.seeds, report.coverage_seeds);
  EXPECT_EQ(estimation.getReport().input_points, upper->size());
  EXPECT_DOUBLE_EQ(estimation.getReport().quad_length, 0.25);
  // The half sphere's area 25.1 over L² = 0.0625: about 400 quads, one seed each at overlap 0,
  // plus the coverage seeds of the surface points between such patches (each only as wide as its quad).
  EXPECT_GT(report.quad_faces, 300u);
  EXPECT_LT(report.quad_faces, 550u);
  EXPECT_EQ(seeds.size(), report.quad_faces + report.coverage_seeds);
  EXPECT_EQ(static_cast<std::size_t>(std::count(estimation.getSeedQuads().begin(), estimation.getSeedQuads().end(), -1)),
            report.coverage_seeds);
  double lowest = 1e9;
  for (const auto& seed : seeds)
    lowest = std::min(lowest, static_cast<double>(seed.z));
  EXPECT_GT(lowest, kCentre.z() - 0.1 * kRadius);
  // The same seeds and frames, bit for bit, on one thread and on two.
  for (const int threads : {1, 2}) {
    estimation.setNumberOfThreads(threads);
    pcl::PointCloud<pcl::PointNormal> again;
    pcl::PointCloud<pcl::ReferenceFrame> again_frames;
    estimation.compute(again, again_frames);
    ASSERT_EQ(again.size(), seeds.size());
    EXPECT_EQ(std::memcmp(again.data(), seeds.data(), sizeof(pcl::PointNormal) * seeds.size()), 0);
    EXPECT_EQ(std::memcmp(again_frames.data(), frames.data(), sizeof(pcl::ReferenceFrame) * frames.size()), 0);
  }
}

TEST(PclQuadFrames, OnTheBunnyMeshSeedsLieOnItAndZFollowsItsNormals)
{
  TriangleMesh bunny;
  readMesh(test_support::dataDir() + "/bunny.obj", bunny);
  cleanMesh(bunny);
  pcl::PolygonMesh::Ptr mesh(new pcl::PolygonMesh);
  toPolygonMesh(bunny, *mesh);
  TriangleMesh as_given;  // the float coordinates the pcl::PolygonMesh holds
  fromPolygonMesh(*mesh, as_given);
  QuadFrameEstimation<pcl::PointXYZ> estimation;
  estimation.setInputPolygonMesh(mesh);
  pcl::PointCloud<pcl::PointNormal> seeds;
  pcl::PointCloud<pcl::ReferenceFrame> frames;
  estimation.compute(seeds, frames);
  EXPECT_FALSE(estimation.getReport().from_cloud);
  Eigen::Vector3d low, high;
  as_given.boundingBox(low, high);
  const double side = (high - low).maxCoeff();
  EXPECT_NEAR(estimation.getReport().quad_length, 0.03 * side, 1e-9 * side);
  ASSERT_GT(seeds.size(), 1000u);
  bool right_handed = false;
  EXPECT_LT(orthonormality(frames, right_handed), 1e-5);
  EXPECT_TRUE(right_handed);
  // Seeds are moved onto the input: their distance to it is float rounding; Z against the face
  // normal where each seed lies (the quads' normals are smoothed: most agree within 30°).
  const PointToMeshDistance surface(as_given);
  std::size_t agreeing = 0;
  double farthest = 0.0;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const auto hit = surface.query(seeds[s].getVector3fMap().cast<double>());
    farthest = std::max(farthest, std::sqrt(hit.squared_distance));
    const Eigen::Vector3d n = as_given.faceNormal(static_cast<std::size_t>(hit.face));
    agreeing += fromReferenceFrame(frames[s]).row(2).dot(n) > std::cos(30.0 * kDegree);
  }
  EXPECT_LT(farthest, 1e-6 * side);
  EXPECT_GE(static_cast<double>(agreeing) / static_cast<double>(seeds.size()), 0.9);
}

TEST(PclQuadFrames, MisuseIsAnError)
{
  pcl::PointCloud<pcl::PointNormal> seeds;
  pcl::PointCloud<pcl::ReferenceFrame> frames;
  QuadFrameEstimation<pcl::PointXYZ> none;
  EXPECT_THROW(none.compute(seeds, frames), Error);  // no input
  pcl::PointCloud<pcl::PointXYZ>::Ptr few(new pcl::PointCloud<pcl::PointXYZ>);
  for (int i = 0; i < 50; ++i)
    few->push_back(pcl::PointXYZ(static_cast<float>(i), 0.f, 0.f));
  QuadFrameEstimation<pcl::PointXYZ> small;
  small.setInputCloud(few);
  try {
    small.compute(seeds, frames);
    ADD_FAILURE() << "no error for 50 points";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("50 finite points, fewer than 100"), std::string::npos) << error.what();
  }
  QuadFrameEstimation<pcl::PointXYZ> negative;
  negative.setInputCloud(sphereCloud<pcl::PointXYZ>());
  negative.setQuadLength(-1.0);
  EXPECT_THROW(negative.compute(seeds, frames), Error);
  negative.setQuadLength(100.0);  // larger than the sphere: fewer than 6 quads
  EXPECT_THROW(negative.compute(seeds, frames), Error);
  pcl::IndicesPtr outside(new pcl::Indices{0, 1, 20000});
  negative.setQuadLength(0.0);
  negative.setIndices(outside);
  EXPECT_THROW(negative.compute(seeds, frames), Error);
}
