// pcl_patchdict denoise on point clouds: PCD fields carried, organisation kept, PLY clouds, errors.
#include "test_support.h"

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <gtest/gtest.h>

#include <cmath>
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
    EXPECT_LT((p.getVector3fMap() - source.getVector3fMap()).norm(), 0.03f);
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
  for (std::size_t i = out.size() - static_cast<std::size_t>(added); i < out.size(); ++i) {
    EXPECT_GT(out[i].z, 0.92f);  // over the cap (z > 0.95) or its rim band
    EXPECT_NEAR(out[i].getVector3fMap().norm(), 1.0f, 0.02f);
    EXPECT_EQ(out[i].intensity, std::round(out[i].intensity));  // copied from an input point
    EXPECT_LT(out[i].intensity, 12000.0f);
  }
}

}  // namespace
