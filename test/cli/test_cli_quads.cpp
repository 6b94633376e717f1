// `pcl_patchdict quads` as a user meets it: a quad mesh of the bundled bunny that meets the
// issue's quality bounds, frames that can be read back, clear errors for bad input.
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

using namespace pcl::patchdict;
using test_support::endsWithOneErrorLine;
using test_support::jsonNumber;
using test_support::q;
using test_support::runTool;

TEST(CliQuads, BunnyQuadMeshMeetsTheQualityBounds)
{
  test_support::TempDir dir;
  const std::string input = test_support::dataDir() + "/bunny.obj";
  const std::string before = test_support::readFile(input);
  const auto result = runTool("quads " + q(input) + " -o " + q(dir.file("quads.obj")) + " --frames " +
                              q(dir.file("frames.ply")) + " --json --threads 2");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_GE(jsonNumber(result.out, "quad_fraction"), 0.9);
  EXPECT_GE(jsonNumber(result.out, "interior_valence4_fraction"), 0.85);
  EXPECT_NEAR(jsonNumber(result.out, "mean_edge_length"), 0.03, 0.15 * 0.03);
  EXPECT_EQ(jsonNumber(result.out, "nonmanifold_edges"), 0.0);
  const double seeds = jsonNumber(result.out, "seeds");
  // Overlap 1: centre + 4 per face, plus a few coverage seeds where no quad reaches (bunny: holes
  // in its base).
  EXPECT_GE(seeds, 5.0 * jsonNumber(result.out, "faces"));
  EXPECT_LE(seeds, 5.0 * jsonNumber(result.out, "faces") + 200.0);
  EXPECT_EQ(test_support::readFile(input), before);

  // The OBJ has real quads ("f a b c d"), in the input's units (the bunny is ~0.15 across).
  std::ifstream obj(dir.file("quads.obj"));
  std::string line;
  std::size_t quads = 0, faces = 0;
  double max_coordinate = 0.0;
  while (std::getline(obj, line)) {
    std::istringstream in(line);
    std::string tag;
    in >> tag;
    if (tag == "f") {
      std::size_t count = 0;
      std::string index;
      while (in >> index)
        ++count;
      ++faces;
      quads += count == 4;
    } else if (tag == "v") {
      double x, y, z;
      in >> x >> y >> z;
      max_coordinate = std::max({max_coordinate, std::abs(x), std::abs(y), std::abs(z)});
    }
  }
  EXPECT_EQ(static_cast<double>(faces), jsonNumber(result.out, "faces"));
  EXPECT_EQ(static_cast<double>(quads), jsonNumber(result.out, "quads"));
  EXPECT_GT(max_coordinate, 0.05);
  EXPECT_LT(max_coordinate, 0.3);

  // The frames file is a point set our reader accepts, one point per seed.
  TriangleMesh frames;
  readMesh(dir.file("frames.ply"), frames);
  EXPECT_EQ(static_cast<double>(frames.vertices.size()), seeds);
}

TEST(CliQuads, BadInputGetsOneErrorLine)
{
  test_support::TempDir dir;
  writeMesh(dir.file("sphere.ply"), makeIcosphere(3, 1.0));
  writeMesh(dir.file("ring.ply"), makeTorus(200, 12, 1.0, 0.02));
  // L larger than the shape (a thin ring, 0.02 thick in unit-cube units, with L = 0.4): a clear
  // error, no output file.
  auto result = runTool("quads " + q(dir.file("ring.ply")) + " -o " + q(dir.file("q.obj")) + " --quad-length 0.4");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_NE(result.err.find("too large"), std::string::npos) << result.err;
  EXPECT_TRUE(test_support::readFile(dir.file("q.obj")).empty());
  // Output equal to the input is refused; the input stays as it was.
  const std::string before = test_support::readFile(dir.file("sphere.ply"));
  result = runTool("quads " + q(dir.file("sphere.ply")) + " -o " + q(dir.file("sphere.ply")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_EQ(test_support::readFile(dir.file("sphere.ply")), before);
  // Options out of range and a wrong output extension.
  for (const char* bad : {"0", "0.6", "1e-5", "x"}) {
    result = runTool("quads " + q(dir.file("sphere.ply")) + " -o " + q(dir.file("q.obj")) + " --quad-length " + bad);
    EXPECT_EQ(result.exit_code, 2) << bad;
  }
  result = runTool("quads " + q(dir.file("sphere.ply")) + " -o " + q(dir.file("q.stl")) + " --quad-length 0.3");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  // Missing file, garbage file.
  result = runTool("quads " + q(dir.file("missing.ply")) + " -o " + q(dir.file("q.obj")));
  EXPECT_EQ(result.exit_code, 1);
  test_support::writeFile(dir.file("garbage.off"), "garbage");
  result = runTool("quads " + q(dir.file("garbage.off")) + " -o " + q(dir.file("q.obj")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
}
