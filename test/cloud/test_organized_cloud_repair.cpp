// GeometricCloudRepair on organised frames (a depth image: filled in place, points on their
// rays, width × height kept) and on hostile clouds (one point, wild depths, copies), class and tool.
#include "test_support.h"

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace {

using pcl::patchdict::GeometricCloudRepair;
using test_support::q;
using test_support::runTool;
using test_support::SyntheticFrame;

const float kNaNf = std::numeric_limits<float>::quiet_NaN();

// A wall with a box in front and the box's shadow, a dropout on the wall; colour = a code of the pixel.
pcl::PointCloud<pcl::PointXYZRGB>::Ptr kinectLikeFrame(SyntheticFrame& frame)
{
  frame.addPlane(Eigen::Vector3d(0.2, -0.3, 1.0), 1.2);
  frame.addBox(100, 140, 20, 100, 0.7);
  frame.sense(0.0012, 0.00285, 7);
  frame.erase(94, 100, 25, 95);
  frame.eraseDisc(40, 60, 8);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(frame.width, frame.height);
  for (std::size_t i = 0; i < frame.points.size(); ++i) {
    auto& p = (*cloud)[i];
    p.getVector3fMap() = frame.points[i].cast<float>();
    p.r = static_cast<std::uint8_t>(i % 251);
    p.g = static_cast<std::uint8_t>((i / 251) % 251);
    p.b = 7;
  }
  cloud->is_dense = false;
  return cloud;
}

using Inpainter = GeometricCloudRepair<pcl::PointXYZRGB>;

// Runs `inpainter` into `out` and checks that the frame went the depth-image way and kept its
// 160 × 120 grid (call it under ASSERT_NO_FATAL_FAILURE).
void processOnTheGrid(Inpainter& inpainter, pcl::PointCloud<pcl::PointXYZRGB>& out)
{
  inpainter.process(out);
  ASSERT_TRUE(inpainter.getReport().depth_image);
  EXPECT_EQ(out.width, 160u);
  EXPECT_EQ(out.height, 120u);
}

TEST(OrganizedCloudRepair, CompleteFillsTheDropoutInPlaceAndLeavesTheShadowOpen)
{
  SyntheticFrame frame(160, 120, 150.0, 79.3, 60.2);
  const auto cloud = kinectLikeFrame(frame);
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(Inpainter::Mode::Complete);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  ASSERT_NO_FATAL_FAILURE(processOnTheGrid(inpainter, out));
  const auto& report = inpainter.getReport();
  const auto& filled = inpainter.getAddedSources();
  EXPECT_EQ(filled.size(), frame.disc(40, 60, 8).size());
  EXPECT_EQ(report.points_added, filled.size());
  EXPECT_EQ(report.organized_fill.holes_filled, 1u);
  for (const auto i : filled) {
    const std::size_t pixel = static_cast<std::size_t>(i);
    EXPECT_NEAR(out[pixel].z, frame.depth[pixel], 0.01);
    EXPECT_EQ(out[pixel].r, (*cloud)[pixel].r);  // the pixel keeps its own colour
    EXPECT_EQ(out[pixel].g, (*cloud)[pixel].g);
  }
  // The shadow stays NaN; measured points are exactly the input's.
  EXPECT_FALSE(std::isfinite(out.at(96, 60).z));
  std::size_t same = 0;
  for (std::size_t i = 0; i < out.size(); ++i)
    if (std::isfinite((*cloud)[i].z))
      same += out[i].x == (*cloud)[i].x && out[i].y == (*cloud)[i].y && out[i].z == (*cloud)[i].z;
  EXPECT_EQ(same, inpainter.getKeptIndices().size());
}

TEST(OrganizedCloudRepair, DenoiseKeepsEveryPointOnItsPixelsRayAndTheGrid)
{
  SyntheticFrame frame(160, 120, 150.0, 79.3, 60.2);
  const auto cloud = kinectLikeFrame(frame);
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  ASSERT_NO_FATAL_FAILURE(processOnTheGrid(inpainter, out));
  const auto& report = inpainter.getReport();
  EXPECT_NEAR(report.depth_noise.exponent, 2.0, 0.5);
  double before = 0.0, after = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(out[i].z) || !std::isfinite((*cloud)[i].z))
      continue;
    const std::size_t column = i % 160, row = i / 160;
    EXPECT_NEAR(report.camera.fx * out[i].x / out[i].z + report.camera.cx, static_cast<double>(column), 1e-3);
    EXPECT_NEAR(report.camera.fy * out[i].y / out[i].z + report.camera.cy, static_cast<double>(row), 1e-3);
    if (column > 10 && column < 85 && row > 10 && row < 110) {  // the wall, away from edges
      before += std::pow((*cloud)[i].z - frame.depth[i], 2);
      after += std::pow(out[i].z - frame.depth[i], 2);
      ++n;
    }
  }
  ASSERT_GT(n, 5000u);
  EXPECT_LT(std::sqrt(after / n), 0.6 * std::sqrt(before / n));
}

TEST(OrganizedCloudRepair, HostileFramesEndInAnErrorOrACorrectResult)
{
  SyntheticFrame frame(160, 120, 150.0, 79.3, 60.2);
  auto cloud = kinectLikeFrame(frame);
  // Every 7th depth written as 1e30: no such point in any output; the pixels are holes like any.
  auto wild = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(*cloud);
  for (std::size_t i = 0; i < wild->size(); i += 7)
    if (std::isfinite((*wild)[i].z))
      (*wild)[i].z = 1e30f;
  for (const auto mode : {Inpainter::Mode::Denoise, Inpainter::Mode::Complete}) {
    Inpainter inpainter;
    inpainter.setInputCloud(wild);
    inpainter.setMode(mode);
    pcl::PointCloud<pcl::PointXYZRGB> out;
    inpainter.process(out);
    EXPECT_GT(inpainter.getReport().gross_outliers, 2000u);
    EXPECT_GT(inpainter.getReport().depth_noise.coefficient, 0.0);
    for (const auto& p : out) {
      ASSERT_FALSE(std::isfinite(p.z) && std::abs(p.z) > 10.0f);
    }
    if (mode == Inpainter::Mode::Complete) {
      EXPECT_GT(inpainter.getAddedSources().size(), 2000u);
    }
  }
  // All finite points one point, or a single one: a clean error.
  auto same = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(*cloud);
  for (auto& p : *same)
    if (std::isfinite(p.z))
      p.x = 0.1f, p.y = 0.2f, p.z = 1.0f;
  Inpainter inpainter;
  inpainter.setInputCloud(same);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  EXPECT_THROW(inpainter.process(out), pcl::patchdict::Error);
  // One valid pixel: a clean error too.
  auto lonely = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(*cloud);
  for (std::size_t i = 0; i < lonely->size(); ++i)
    if (i != 60 * 160 + 40 + 20)
      (*lonely)[i].x = (*lonely)[i].y = (*lonely)[i].z = kNaNf;
  inpainter.setInputCloud(lonely);
  EXPECT_THROW(inpainter.process(out), pcl::patchdict::Error);
  // ±inf coordinates are no points.
  auto infinite = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>(*cloud);
  for (std::size_t i = 0; i < infinite->size(); i += 11)
    (*infinite)[i].x = (i % 2) ? std::numeric_limits<float>::infinity() : -std::numeric_limits<float>::infinity();
  inpainter.setInputCloud(infinite);
  inpainter.setMode(Inpainter::Mode::Complete);
  inpainter.process(out);
  EXPECT_TRUE(inpainter.getReport().depth_image);
  for (const auto& p : out)
    ASSERT_TRUE(std::isfinite(p.x) == std::isfinite(p.z));
}

TEST(OrganizedCloudRepair, Float32TerrainFarFromTheOriginIsFilledWhereItIs)
{
  // An airborne patch in UTM metres as float32 (ulp 0.5 m at 4.5e6): 1 m samples, a 10 m hole.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (int i = 0; i < 80; ++i)
    for (int j = 0; j < 80; ++j) {
      const double u = i + jitter(rng), v = j + jitter(rng);
      if ((u - 40) * (u - 40) + (v - 40) * (v - 40) < 25.0)
        continue;
      pcl::PointXYZ p;
      p.x = static_cast<float>(512000.0 + u);
      p.y = static_cast<float>(4500000.0 + v);
      p.z = static_cast<float>(100.0 + 0.05 * u + 0.02 * v);
      cloud->push_back(p);
    }
  GeometricCloudRepair<pcl::PointXYZ> inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(GeometricCloudRepair<pcl::PointXYZ>::Mode::Complete);
  pcl::PointCloud<pcl::PointXYZ> out;
  inpainter.process(out);
  EXPECT_TRUE(inpainter.getReport().height_field_used);
  ASSERT_GT(inpainter.getReport().points_added, 40u);
  for (std::size_t k = cloud->size(); k < out.size(); ++k) {
    const double u = out[k].x - 512000.0, v = out[k].y - 4500000.0;
    EXPECT_LT((u - 40) * (u - 40) + (v - 40) * (v - 40), 49.0);        // in the hole
    EXPECT_NEAR(out[k].z, 100.0 + 0.05 * u + 0.02 * v, 0.05);          // on the slope
  }
}

TEST(OrganizedCloudRepair, ExactCopiesFollowTheirFirstPoint)
{
  std::mt19937 rng(9);
  std::normal_distribution<double> gauss(0.0, 1.0);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>>();
  for (int i = 0; i < 1500; ++i) {
    const Eigen::Vector3d p = Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)).normalized() * (1.0 + 0.005 * gauss(rng));
    pcl::PointXYZRGB point;
    point.getVector3fMap() = p.cast<float>();
    for (int copy = 0; copy < 6; ++copy)
      cloud->push_back(point);
  }
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  pcl::PointCloud<pcl::PointXYZRGB> out;
  inpainter.process(out);
  EXPECT_EQ(inpainter.getReport().duplicate_points, 7500u);
  ASSERT_EQ(inpainter.getKeptIndices().size(), out.size());
  ASSERT_GT(out.size(), 8000u);
  std::vector<long> output_of(cloud->size(), -1);
  for (std::size_t k = 0; k < out.size(); ++k)
    output_of[static_cast<std::size_t>(inpainter.getKeptIndices()[k])] = static_cast<long>(k);
  double moved = 0.0;
  std::size_t compared = 0;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const long k = output_of[i], first = output_of[i - i % 6];
    EXPECT_EQ(k < 0, first < 0);  // a copy is kept exactly when its first is
    if (k < 0 || first < 0)
      continue;
    moved += (out[k].getVector3fMap() - (*cloud)[i].getVector3fMap()).norm();
    EXPECT_EQ(out[k].getVector3fMap(), out[first].getVector3fMap());
    ++compared;
  }
  EXPECT_GT(compared, 8000u);
  EXPECT_GT(moved, 0.0);  // the copies were denoised, not passed over
}

TEST(OrganizedCloudRepair, ToolKeepsTheGridAndRefusesAOnePointFrame)
{
  test_support::TempDir dir;
  SyntheticFrame frame(160, 120, 150.0, 79.3, 60.2);
  const auto cloud = kinectLikeFrame(frame);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("frame.pcd"), *cloud), 0);
  for (const std::string command : {"fill-holes", "denoise"}) {
    const auto result = runTool(command + " " + q(dir.file("frame.pcd")) + " -o " + q(dir.file("out.pcd")) + " --json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    pcl::PointCloud<pcl::PointXYZRGB> out;
    ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
    EXPECT_EQ(out.width, 160u);
    EXPECT_EQ(out.height, 120u);
    if (command == "fill-holes") {
      EXPECT_EQ(test_support::jsonNumber(result.out, "added"), static_cast<double>(frame.disc(40, 60, 8).size()));
      EXPECT_NE(result.out.find("\"filled_pixels\": ["), std::string::npos);
      for (std::size_t i = 0; i < out.size(); ++i) {  // measured pixels written back exactly
        if (std::isfinite((*cloud)[i].z)) {
          ASSERT_EQ(out[i].z, (*cloud)[i].z);
        }
      }
    }
  }
  auto same = *cloud;
  for (auto& p : same)
    if (std::isfinite(p.z))
      p.x = 0.1f, p.y = 0.2f, p.z = 1.0f;
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("same.pcd"), same), 0);
  for (const std::string command : {"fill-holes", "denoise"}) {
    const auto result = runTool(command + " " + q(dir.file("same.pcd")) + " -o " + q(dir.file("bad.pcd")));
    EXPECT_NE(result.exit_code, 0);
    EXPECT_TRUE(test_support::endsWithOneErrorLine(result.err)) << result.err;
    EXPECT_NE(result.err.find("all at one place"), std::string::npos) << result.err;
    EXPECT_TRUE(test_support::readFile(dir.file("bad.pcd")).empty());
  }
  // One row and one column: organised in name only; handled as unorganised, never a crash.
  pcl::PointCloud<pcl::PointXYZRGB> row(160, 1), column(1, 120);
  for (std::size_t c = 0; c < 160; ++c)
    row[c] = (*cloud)[60 * 160 + c];
  for (std::size_t r = 0; r < 120; ++r)
    column[r] = (*cloud)[r * 160 + 20];
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("row.pcd"), row), 0);
  ASSERT_EQ(pcl::io::savePCDFileBinary(dir.file("column.pcd"), column), 0);
  for (const std::string file : {"row.pcd", "column.pcd"}) {
    const auto result = runTool("fill-holes " + q(dir.file(file)) + " -o " + q(dir.file("line.pcd")));
    EXPECT_TRUE(result.exit_code == 0 || test_support::endsWithOneErrorLine(result.err)) << result.err;
  }
}

}  // namespace
