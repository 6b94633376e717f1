// The fill-holes command over HoleFilling: holes filled with the input vertices kept, the --json
// report, and one-line errors that never overwrite the input.
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/hole_filling.h>
#include <pcl_patchdict/geometry/hole_triangulation.h>
#include <pcl_patchdict/geometry/mesh_fairing.h>
#include <pcl_patchdict/geometry/mesh_hygiene.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/mesh_topology.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include "geometry/hole_test_shapes.h"

#include <gtest/gtest.h>

#include <filesystem>

#include <chrono>
#include <cstdio>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>

using namespace pcl::patchdict;
using namespace hole_test;
using test_support::endsWithOneErrorLine;
using test_support::isOneLine;
using test_support::q;
using test_support::runTool;


TEST(HoleFillingCli, FillsHolesKeepsInputVerticesAndReportsJson)
{
  test_support::TempDir dir;
  const TriangleMesh holed = sphereWithHoles(3, 0.4, {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1)});
  writeMesh(dir.file("holed.ply"), holed);
  const std::string before = test_support::readFile(dir.file("holed.ply"));
  const auto result = runTool("fill-holes " + q(dir.file("holed.ply")) + " --no-patches -o " + q(dir.file("out.ply")) +
                              " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("\"holes_found\": 2"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("\"holes_filled\": 2"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("\"triangulation\": "), std::string::npos) << result.out;
  EXPECT_EQ(test_support::readFile(dir.file("holed.ply")), before);
  TriangleMesh out;
  readMesh(dir.file("out.ply"), out);
  ASSERT_GT(out.vertices.size(), holed.vertices.size());
  for (std::size_t v = 0; v < holed.vertices.size(); ++v)
    ASSERT_EQ(out.vertices[v], holed.vertices[v]) << v;
  EXPECT_EQ(inspectMesh(out).boundary_loops, 0u);

  // --max-hole-edges 1: nothing is small enough; both holes reported as skipped.
  const auto limited = runTool("fill-holes " + q(dir.file("holed.ply")) + " --no-patches --max-hole-edges 1 -o " +
                               q(dir.file("out2.off")) + " --json");
  ASSERT_EQ(limited.exit_code, 0) << limited.err;
  EXPECT_NE(limited.out.find("\"too many edges\": 2"), std::string::npos) << limited.out;
}

TEST(HoleFillingCli, ErrorsAreOneLineAndTheInputIsNeverOverwritten)
{
  test_support::TempDir dir;
  writeMesh(dir.file("in.ply"), sphereWithHoles(2, 0.5, {Eigen::Vector3d(0, 0, 1)}));
  const std::string before = test_support::readFile(dir.file("in.ply"));

  auto result = runTool("fill-holes " + q(dir.file("in.ply")) + " --no-patches -o " + q(dir.file("in.ply")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_EQ(test_support::readFile(dir.file("in.ply")), before);

  result = runTool("fill-holes " + q(dir.file("missing.ply")) + " --no-patches -o " + q(dir.file("out.ply")) + " --quiet");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;

  test_support::writeFile(dir.file("bad.ply"), "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n0 0 0\n");
  result = runTool("fill-holes " + q(dir.file("bad.ply")) + " --no-patches -o " + q(dir.file("out.ply")) + " --quiet");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_TRUE(test_support::readFile(dir.file("out.ply")).empty());

  // A dictionary and --no-patches contradict each other: a usage error, nothing written.
  result = runTool("fill-holes " + q(dir.file("in.ply")) + " --no-patches --dict d.pdd -o " + q(dir.file("out3.ply")));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(isOneLine(result.err)) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("out3.ply")));

  result = runTool("fill-holes " + q(dir.file("in.ply")) + " --no-patches -o " + q(dir.file("out.ply")) +
                   " --max-hole-edges -3");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_TRUE(isOneLine(result.err)) << result.err;
}
