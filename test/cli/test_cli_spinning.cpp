// pcl_patchdict on a real spinning-LiDAR frame (the bundled Ouster OS1-32 street frame): the sensor
// model saved and reused, the grid and every field kept, a frame of another sensor and hostile grids
// refused in one line with no output, an unorganised scan with rings put back on its grid.
#include "test_support.h"

#include <pcl_patchdict/cloud/sensor_model.h>
#include <pcl_patchdict/io/sensor_model_io.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <random>

namespace {

using test_support::TempDir;
using test_support::jsonNumber;
using test_support::q;
using test_support::readFile;
using test_support::runTool;

std::string frame() { return test_support::dataDir() + "/ouster_os1_32_street.pcd"; }

// One line on stderr (the runs below are --quiet: no progress), exit 1, no output file.
void expectRefused(const test_support::ToolResult& result, const std::string& output, const std::string& words)
{
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find(words), std::string::npos) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_FALSE(std::filesystem::exists(output));
}

TEST(CliSpinning, TheSavedSensorModelRepairsTheNextFrameAndKeepsTheGrid)
{
  TempDir dir;
  const std::string before = readFile(frame());
  const auto info = runTool("info " + q(frame()) + " --save-sensor-model " + q(dir.file("os1.txt")) + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("\"kind\": \"spinning\""), std::string::npos) << info.out;
  EXPECT_EQ(jsonNumber(info.out, "beams"), 32.0);
  EXPECT_NEAR(jsonNumber(info.out, "quantum"), 0.001, 1e-12);
  EXPECT_NEAR(jsonNumber(info.out, "beam_origin_radius"), 0.0158, 0.001);  // Ouster's 15.8 mm
  const auto run = runTool("fill-holes " + q(frame()) + " -o " + q(dir.file("out.pcd")) + " --denoise --sensor-model " +
                           q(dir.file("os1.txt")) + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(readFile(frame()), before);
  EXPECT_NE(run.out.find("\"sensor_model_given\": true"), std::string::npos);
  EXPECT_GT(jsonNumber(run.out, "pixels_filled"), 20.0);  // the frame's own dropouts on one surface
  pcl::PCLPointCloud2 in, out;
  ASSERT_EQ(pcl::io::loadPCDFile(frame(), in), 0);
  ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
  EXPECT_EQ(out.width, 1024u);
  EXPECT_EQ(out.height, 32u);
  ASSERT_EQ(out.fields.size(), in.fields.size());
  // Every pixel keeps its ring; the filled ones get an interpolated intensity (not the 0 of no return).
  const auto field = [](const pcl::PCLPointCloud2& c, const char* name) {
    return *std::find_if(c.fields.begin(), c.fields.end(), [&](const auto& f) { return f.name == name; });
  };
  const auto at = [](const pcl::PCLPointCloud2& c, const pcl::PCLPointField& f, std::size_t i, auto value) {
    std::memcpy(&value, c.data.data() + i * c.point_step + f.offset, sizeof value);
    return value;
  };
  std::size_t filled = 0;
  for (std::size_t i = 0; i < 1024u * 32u; ++i) {
    EXPECT_EQ(at(out, field(out, "ring"), i, std::uint16_t{}), at(in, field(in, "ring"), i, std::uint16_t{}));
    const bool was = std::isfinite(at(in, field(in, "x"), i, 0.0f)), is = std::isfinite(at(out, field(out, "x"), i, 0.0f));
    EXPECT_TRUE(is || !was) << i;  // no measured pixel lost
    if (is && !was) {
      ++filled;
      EXPECT_GT(at(out, field(out, "intensity"), i, 0.0f), 0.0f) << i;
    }
  }
  EXPECT_EQ(static_cast<double>(filled), jsonNumber(run.out, "pixels_filled"));
}

TEST(CliSpinning, AFrameOfAnotherSensorAndABadModelAreRefusedInOneLine)
{
  TempDir dir;
  ASSERT_EQ(runTool("info " + q(frame()) + " --save-sensor-model " + q(dir.file("os1.txt"))).exit_code, 0);
  const std::string kinect = test_support::dataDir() + "/kinect_desk_qvga.pcd";
  expectRefused(runTool("denoise " + q(kinect) + " -o " + q(dir.file("k.pcd")) + " --sensor-model " + q(dir.file("os1.txt")) + " --quiet"),
                dir.file("k.pcd"), "the sensor model given is 1024 x 32");
  // The same grid, every beam 1° higher: another sensor's beams (a well-formed model that does not fit).
  pcl::patchdict::SensorModel other = pcl::patchdict::loadSensorModel(dir.file("os1.txt"));
  for (double& e : other.spinning.elevation)
    e += 0.0175;
  pcl::patchdict::saveSensorModel(dir.file("other.txt"), other);
  expectRefused(runTool("fill-holes " + q(frame()) + " -o " + q(dir.file("o.pcd")) + " --sensor-model " +
                        q(dir.file("other.txt")) + " --quiet"),
                dir.file("o.pcd"), "does not fit the sensor model");
  test_support::writeFile(dir.file("bad.txt"), "pcl_patchdict sensor model 1\nkind spinning\nwidth 1024\n");
  expectRefused(runTool("denoise " + q(frame()) + " -o " + q(dir.file("b.pcd")) + " --sensor-model " + q(dir.file("bad.txt")) + " --quiet"),
                dir.file("b.pcd"), "sensor model: 'height' missing");
}

TEST(CliSpinning, OneAndTwoThreadsWriteTheSameBytes)
{
  TempDir dir;
  for (const char* threads : {"1", "2"}) {
    const auto run = runTool("fill-holes " + q(frame()) + " -o " + q(dir.file(std::string("t") + threads + ".pcd")) +
                             " --denoise --quiet --threads " + threads);
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  EXPECT_EQ(readFile(dir.file("t1.pcd")), readFile(dir.file("t2.pcd")));
}

// Rows shuffled (beams out of order) and the grid transposed: refused, never repaired as a cloud.
TEST(CliSpinning, HostileGridsAreRefusedInOneLine)
{
  TempDir dir;
  pcl::PCLPointCloud2 in;
  ASSERT_EQ(pcl::io::loadPCDFile(frame(), in), 0);
  const std::size_t W = in.width, H = in.height, step = in.point_step;
  pcl::PCLPointCloud2 shuffled = in, transposed = in;
  std::vector<std::size_t> rows(H);
  std::iota(rows.begin(), rows.end(), 0);
  std::shuffle(rows.begin(), rows.end(), std::mt19937(3));
  transposed.width = static_cast<std::uint32_t>(H);
  transposed.height = static_cast<std::uint32_t>(W);
  transposed.row_step = static_cast<std::uint32_t>(H * step);
  for (std::size_t r = 0; r < H; ++r)
    for (std::size_t c = 0; c < W; ++c) {
      std::memcpy(&shuffled.data[(r * W + c) * step], &in.data[(rows[r] * W + c) * step], step);
      std::memcpy(&transposed.data[(c * H + r) * step], &in.data[(r * W + c) * step], step);
    }
  ASSERT_EQ(pcl::io::savePCDFile(dir.file("shuffled.pcd"), shuffled, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), true), 0);
  ASSERT_EQ(pcl::io::savePCDFile(dir.file("transposed.pcd"), transposed, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), true), 0);
  expectRefused(runTool("fill-holes " + q(dir.file("shuffled.pcd")) + " -o " + q(dir.file("s.pcd")) + " --quiet"), dir.file("s.pcd"),
                "the beams are out of order");
  expectRefused(runTool("denoise " + q(dir.file("transposed.pcd")) + " -o " + q(dir.file("t.pcd")) + " --quiet"), dir.file("t.pcd"),
                "its grid is transposed");
}

// The frame's measured points, shuffled, without their grid: the rings put them back, the repair
// writes them in the file's order followed by the filled pixels, as many as on the organised frame.
TEST(CliSpinning, AnUnorganisedScanWithRingsIsRepairedOnItsGrid)
{
  TempDir dir;
  pcl::PCLPointCloud2 in;
  ASSERT_EQ(pcl::io::loadPCDFile(frame(), in), 0);
  const pcl::PCLPointField& x = in.fields[0];
  ASSERT_EQ(x.name, "x");
  std::vector<std::size_t> finite;
  for (std::size_t i = 0; i < std::size_t(in.width) * in.height; ++i) {
    float v;
    std::memcpy(&v, &in.data[i * in.point_step + x.offset], sizeof v);
    if (std::isfinite(v))
      finite.push_back(i);
  }
  std::shuffle(finite.begin(), finite.end(), std::mt19937(7));
  pcl::PCLPointCloud2 scan = in;
  scan.width = static_cast<std::uint32_t>(finite.size());
  scan.height = 1;
  scan.row_step = scan.width * scan.point_step;
  scan.data.resize(scan.row_step);
  for (std::size_t k = 0; k < finite.size(); ++k)
    std::memcpy(&scan.data[k * in.point_step], &in.data[finite[k] * in.point_step], in.point_step);
  ASSERT_EQ(pcl::io::savePCDFile(dir.file("scan.pcd"), scan, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity(), true), 0);
  const auto organised = runTool("fill-holes " + q(frame()) + " -o " + q(dir.file("grid.pcd")) + " --json");
  const auto unorganised = runTool("fill-holes " + q(dir.file("scan.pcd")) + " -o " + q(dir.file("out.pcd")) + " --json");
  ASSERT_EQ(organised.exit_code, 0) << organised.err;
  ASSERT_EQ(unorganised.exit_code, 0) << unorganised.err;
  const double added = jsonNumber(organised.out, "pixels_filled");
  EXPECT_GT(added, 20.0);
  EXPECT_EQ(jsonNumber(unorganised.out, "pixels_filled"), added);
  pcl::PCLPointCloud2 out;
  ASSERT_EQ(pcl::io::loadPCDFile(dir.file("out.pcd"), out), 0);
  EXPECT_EQ(out.height, 1u);
  EXPECT_EQ(static_cast<double>(out.width), static_cast<double>(finite.size()) + added);
  // The input's records first, as they were (fill-holes keeps measured points).
  EXPECT_EQ(0, std::memcmp(out.data.data(), scan.data.data(), scan.data.size()));
}

}  // namespace
