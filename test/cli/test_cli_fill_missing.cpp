// `pcl_patchdict fill-missing` (formerly `inpaint`) as a user meets it: the bi-Laplacian base (--no-patches) recovers
// missing vertices of a plane exactly and keeps the known ones; bad input gets one error line.
#include <pcl_patchdict/io/index_io.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace pcl::patchdict;
using test_support::endsWithOneErrorLine;
using test_support::jsonNumber;
using test_support::q;
using test_support::runTool;

TEST(CliFillMissing, NoPatchesRecoversAPlaneAndKeepsKnownVertices)
{
  test_support::TempDir dir;
  TriangleMesh plane = makePlaneGrid(30, 30, 1.0, 1.0);
  for (auto& v : plane.vertices)
    v.z() = 0.3 * v.x() - 0.2 * v.y() + 1.0;  // a tilted plane: the bi-Laplacian's known answer
  const TriangleMesh truth = plane;
  // Every third vertex at least 3 rings inside is missing (so every Laplacian row that touches a
  // missing vertex is an interior one, zero on a plane); its stored position is junk.
  std::vector<int> missing;
  for (int j = 3; j < 28; ++j)
    for (int i = 3; i < 28; ++i)
      if ((i + 2 * j) % 3 == 0) {
        const int v = j * 31 + i;
        missing.push_back(v);
        plane.vertices[static_cast<std::size_t>(v)] += Eigen::Vector3d(0.01, -0.02, 0.3);
      }
  writeMesh(dir.file("holed.ply"), plane);
  writeIndexFile(dir.file("missing.txt"), missing);
  const std::string before = test_support::readFile(dir.file("holed.ply"));
  const auto result = runTool("fill-missing " + q(dir.file("holed.ply")) + " --missing " + q(dir.file("missing.txt")) +
                              " --no-patches -o " + q(dir.file("out.ply")) + " --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  TriangleMesh out;
  readMesh(dir.file("out.ply"), out);
  ASSERT_EQ(out.vertices.size(), truth.vertices.size());
  EXPECT_EQ(out.faces, truth.faces);
  double worst = 0.0;
  for (const int v : missing)
    worst = std::max(worst, (out.vertices[static_cast<std::size_t>(v)] - truth.vertices[static_cast<std::size_t>(v)]).norm());
  EXPECT_LT(worst, 1e-9);
  std::vector<char> is_missing(truth.vertices.size(), 0);
  for (const int v : missing)
    is_missing[static_cast<std::size_t>(v)] = 1;
  for (std::size_t v = 0; v < truth.vertices.size(); ++v) {
    if (!is_missing[v]) {
      EXPECT_EQ(out.vertices[v], plane.vertices[v]);  // known vertices bit-identical
    }
  }
  EXPECT_EQ(test_support::readFile(dir.file("holed.ply")), before);
  // The former name still runs the same repair, to the same bytes.
  const auto former = runTool("inpaint " + q(dir.file("holed.ply")) + " --missing " + q(dir.file("missing.txt")) +
                              " --no-patches -o " + q(dir.file("former.ply")) + " --json");
  ASSERT_EQ(former.exit_code, 0) << former.err;
  EXPECT_NE(former.out.find("\"command\": \"fill-missing\""), std::string::npos) << former.out;
  EXPECT_EQ(test_support::readFile(dir.file("former.ply")), test_support::readFile(dir.file("out.ply")));

  // Bad input: an index out of range, output = input, --dict with --no-patches, a missing file.
  test_support::writeFile(dir.file("bad.txt"), "5\n100000\n");
  auto bad = runTool("fill-missing " + q(dir.file("holed.ply")) + " --missing " + q(dir.file("bad.txt")) +
                     " --no-patches -o " + q(dir.file("o.ply")));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(bad.err)) << bad.err;
  bad = runTool("fill-missing " + q(dir.file("holed.ply")) + " --missing " + q(dir.file("missing.txt")) +
                " --no-patches -o " + q(dir.file("holed.ply")));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(test_support::readFile(dir.file("holed.ply")), before);
  bad = runTool("fill-missing " + q(dir.file("holed.ply")) + " --missing " + q(dir.file("missing.txt")) +
                " --no-patches --dict x.pdd -o " + q(dir.file("o.ply")));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_TRUE(test_support::isOneLine(bad.err)) << bad.err;
  bad = runTool("fill-missing " + q(dir.file("nothing.ply")) + " --missing " + q(dir.file("missing.txt")) +
                " --no-patches -o " + q(dir.file("o.ply")));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(bad.err)) << bad.err;
  EXPECT_TRUE(test_support::readFile(dir.file("o.ply")).empty());
}
