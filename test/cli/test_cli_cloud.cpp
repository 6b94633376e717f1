// pcl_patchdict denoise on point clouds: PCD fields carried, organisation kept, PLY clouds, errors.
#include "test_support.h"

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <cstring>
#include <random>

namespace {

using test_support::TempDir;
using test_support::jsonNumber;
using test_support::q;
using test_support::readFile;
using test_support::runTool;

// Noisy unit sphere, intensity = the point's index (so each output point names its input).
pcl::PointCloud<pcl::PointXYZI> sphere(std::size_t n, std::size_t outliers)
{
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.5, 1.5);
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (std::size_t i = 0; i < n + outliers; ++i) {
    Eigen::Vector3d p(gauss(rng), gauss(rng), gauss(rng));
    p = i < n ? Eigen::Vector3d(p.normalized() * (1.0 + 0.005 * gauss(rng))) : Eigen::Vector3d(uniform(rng), uniform(rng), uniform(rng));
    pcl::PointXYZI point;
    point.x = static_cast<float>(p.x());
    point.y = static_cast<float>(p.y());
    point.z = static_cast<float>(p.z());
    point.intensity = static_cast<float>(i);
    cloud.push_back(point);
  }
  return cloud;
}

TEST(CliCloud, PcdKeepsEveryFieldItDoesNotTouchAndTheInputFile)
{
  TempDir dir;
  const auto cloud = sphere(5000, 50);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("in.pcd"), cloud), 0);
  const std::string before = readFile(dir.file("in.pcd"));
  const auto result = runTool("denoise " + q(dir.file("in.pcd")) + " -o " + q(dir.file("out.pcd")) + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(readFile(dir.file("in.pcd")), before);
  pcl::PointCloud<pcl::PointXYZI> out;
  ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
  EXPECT_EQ(static_cast<double>(out.size()), jsonNumber(result.out, "points_out"));
  EXPECT_EQ(jsonNumber(result.out, "points_in"), 5050.0);
  EXPECT_GE(out.size(), std::size_t{4750});
  EXPECT_GE(jsonNumber(result.out, "removed_as_outliers"), 40.0);
  float previous = -1.0f;
  for (const auto& p : out) {
    ASSERT_GT(p.intensity, previous);  // input order
    previous = p.intensity;
    const auto& source = cloud[static_cast<std::size_t>(p.intensity)];
    if (p.intensity < 5000.0f) {  // a sample moves by its noise; a former outlier near the sphere is projected
      EXPECT_LT((p.getVector3fMap() - source.getVector3fMap()).norm(), 0.03f);
    }
    EXPECT_NEAR(p.getVector3fMap().norm(), 1.0f, 0.01f);
  }
}

TEST(CliCloud, OrganisedPcdKeepsItsGridAndPlyCloudsWork)
{
  TempDir dir;
  pcl::PointCloud<pcl::PointXYZ> grid(80, 60);
  std::mt19937 rng(12);
  std::normal_distribution<double> gauss(0.0, 0.002);
  for (std::uint32_t r = 0; r < grid.height; ++r)
    for (std::uint32_t c = 0; c < grid.width; ++c) {
      auto& p = grid.at(c, r);
      p.x = c * 0.01f;
      p.y = r * 0.01f;
      p.z = static_cast<float>(1.0 + gauss(rng));
      if (c < 10 && r < 10)
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
    }
  grid.is_dense = false;
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("grid.pcd"), grid), 0);
  auto result = runTool("denoise " + q(dir.file("grid.pcd")) + " -o " + q(dir.file("out.pcd")) + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  pcl::PointCloud<pcl::PointXYZ> out;
  ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
  EXPECT_EQ(out.width, 80u);
  EXPECT_EQ(out.height, 60u);
  EXPECT_FALSE(std::isfinite(out.at(3, 3).x));
  EXPECT_NEAR(out.at(40, 30).z, 1.0f, 0.003f);
  EXPECT_EQ(jsonNumber(result.out, "nonfinite_points"), 100.0);

  // Vertex-only PLY in and out.
  const auto ply = runTool("denoise " + q(dir.file("out.pcd")) + " -o " + q(dir.file("flat.ply")) + " --quiet");
  ASSERT_EQ(ply.exit_code, 0) << ply.err;
  result = runTool("denoise " + q(dir.file("flat.ply")) + " -o " + q(dir.file("again.ply")) + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GT(jsonNumber(result.out, "points_out"), 4500.0);
}

TEST(CliCloud, Float64PcdFarFromTheOriginKeepsItsPrecision)
{
  // A georeferenced scan: a 1 m plane at (500 km, 5400 km) with 2 mm noise, stored as float64.
  TempDir dir;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 0.002);
  std::string body;
  const int n = 5000;
  for (int i = 0; i < n; ++i) {
    const double xyz[3] = {5e5 + uniform(rng), 5.4e6 + uniform(rng), 100.0 + gauss(rng)};
    body.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  }
  const std::string header = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " +
                             std::to_string(n) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " + std::to_string(n) +
                             "\nDATA binary\n";
  test_support::writeFile(dir.file("geo.pcd"), header + body);
  const auto result = runTool("denoise " + q(dir.file("geo.pcd")) + " -o " + q(dir.file("out.pcd")) + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GE(jsonNumber(result.out, "points_out"), 4900.0);
  // σ = 2 mm in units of the largest side (1 m): found within 25 %.
  EXPECT_NEAR(jsonNumber(result.out, "noise_sigma") / 0.002, 1.0, 0.25);
  pcl::PCLPointCloud2 out;
  ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
  ASSERT_EQ(out.fields.size(), 3u);
  EXPECT_EQ(out.fields[0].datatype, pcl::PCLPointField::FLOAT64);
  double spread = 0.0, mean = 0.0;
  const std::size_t points = static_cast<std::size_t>(out.width) * out.height;
  for (std::size_t i = 0; i < points; ++i) {
    double xyz[3];
    std::memcpy(xyz, out.data.data() + out.point_step * i, sizeof xyz);
    EXPECT_GT(xyz[0], 5e5 - 0.01);
    EXPECT_LT(xyz[1], 5.4e6 + 1.01);
    mean += xyz[2];
    spread += (xyz[2] - 100.0) * (xyz[2] - 100.0);
  }
  EXPECT_NEAR(mean / static_cast<double>(points), 100.0, 0.001);
  EXPECT_LT(std::sqrt(spread / static_cast<double>(points)), 0.5 * 0.002);  // denoised, not rounded
}

TEST(CliCloud, TooFewPointsAndMeshOutputsAreRefusedWithOneLine)
{
  TempDir dir;
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("few.pcd"), sphere(60, 0)), 0);
  auto result = runTool("denoise " + q(dir.file("few.pcd")) + " -o " + q(dir.file("out.pcd")));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_TRUE(test_support::endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_TRUE(readFile(dir.file("out.pcd")).empty());
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("ok.pcd"), sphere(2000, 0)), 0);
  result = runTool("denoise " + q(dir.file("ok.pcd")) + " -o " + q(dir.file("out.obj")));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.err.find("cloud file"), std::string::npos) << result.err;
}

TEST(CliCloud, FillHolesAddsPointsInAHoleAndCarriesFieldsFromTheirNeighbours)
{
  TempDir dir;
  pcl::PointCloud<pcl::PointXYZI> cloud;
  for (const auto& p : sphere(12000, 0))
    if (p.z < 0.95f)  // a cap of radius ≈ 0.31 removed
      cloud.push_back(p);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("holed.pcd"), cloud), 0);
  const auto result = runTool("fill-holes " + q(dir.file("holed.pcd")) + " -o " + q(dir.file("out.pcd")) +
                              " --max-hole-diameter 0.5 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonNumber(result.out, "filled"), 1.0);
  const double added = jsonNumber(result.out, "added");
  // The cap's area (2π · 0.05) at the input's density (≈ 11,700 points on 4π − 0.31).
  EXPECT_NEAR(added / (cloud.size() * 0.1 * M_PI / (4.0 * M_PI - 0.1 * M_PI)), 1.0, 0.3);
  pcl::PointCloud<pcl::PointXYZI> out;
  ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
  ASSERT_EQ(static_cast<double>(out.size()), jsonNumber(result.out, "points_out"));
  // The input points first, in order and bit-identical (fields included); then the new ones.
  ASSERT_EQ(out.size(), cloud.size() + static_cast<std::size_t>(added));
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_EQ(out[i].x, cloud[i].x);
    ASSERT_EQ(out[i].y, cloud[i].y);
    ASSERT_EQ(out[i].z, cloud[i].z);
    ASSERT_EQ(out[i].intensity, cloud[i].intensity);
  }
  std::size_t same_as_nearest = 0;
  for (std::size_t i = cloud.size(); i < out.size(); ++i) {
    EXPECT_GT(out[i].z, 0.92f);  // over the cap (z > 0.95) or its rim band
    EXPECT_NEAR(out[i].getVector3fMap().norm(), 1.0f, 0.02f);
    // Fields come from the nearest input point (of the denoised surface: the nearest of the input
    // almost always).
    std::size_t nearest = 0;
    for (std::size_t j = 1; j < cloud.size(); ++j)
      if ((cloud[j].getVector3fMap() - out[i].getVector3fMap()).squaredNorm() <
          (cloud[nearest].getVector3fMap() - out[i].getVector3fMap()).squaredNorm())
        nearest = j;
    same_as_nearest += out[i].intensity == cloud[nearest].intensity ? 1 : 0;
  }
  EXPECT_GT(static_cast<double>(same_as_nearest), 0.9 * added);
}

}  // namespace

// reconstruct on a cloud outputs the patches' points: --rule (how a mesh vertex reads its patches)
// and --samples (a mesh's surface score) would be ignored, so they are refused (issue 26).
TEST(CliCloud, ReconstructRefusesTheMeshOnlyOptions)
{
  TempDir dir;
  const std::string cloud = q(std::string(PCL_PATCHDICT_DATA_DIR) + "/kinect_desk_qvga.pcd");
  for (const std::string option : {" --rule bin-centres", " --samples 5000"}) {
    const auto result = runTool("reconstruct " + cloud + " -o " + q(dir.file("out.ply")) + option + " --quiet");
    EXPECT_EQ(result.exit_code, 2) << option << "\n" << result.err;
    EXPECT_TRUE(test_support::isOneLine(result.err)) << result.err;
    EXPECT_NE(result.err.find(option.substr(1, option.find(' ', 1) - 1)), std::string::npos) << result.err;
    EXPECT_FALSE(std::filesystem::exists(dir.file("out.ply")));
  }
}
