// `pcl_patchdict patches` and `pcl_patchdict reconstruct` as a user meets them: files that load
// back, round trips scored in --json, outputs in the input's coordinates, one-line errors.
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/normalization.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_set_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

using namespace pcl::patchdict;
using test_support::runTool;

using test_support::endsWithOneErrorLine;
using test_support::jsonNumber;
using test_support::q;

namespace {

// A smooth relief, moved far from the unit cube (×50, shifted) so that a forgotten inverse
// normalisation shows.
TriangleMesh relief()
{
  TriangleMesh mesh = makeSinusoidalRelief(60, 60, 0.05, 0.5);
  for (auto& v : mesh.vertices)
    v = 50.0 * v + Eigen::Vector3d(100.0, -20.0, 7.0);
  return mesh;
}

// The vertices of a radius-2 icosphere of `levels` written as a face-less PLY to `path` (a cloud on
// a known sphere); returns them.
TriangleMesh writeSphereCloud(const std::string& path, int levels)
{
  TriangleMesh cloud = makeIcosphere(levels, 2.0);
  cloud.faces.clear();
  writeMesh(path, cloud);
  return cloud;
}

}  // namespace

TEST(CliPatches, WritesALoadablePatchSetAndASheetDeterministically)
{
  test_support::TempDir dir;
  const TriangleMesh mesh = relief();
  writeMesh(dir.file("relief.ply"), mesh);
  // Random placement: its patch count has a closed form (the quad placement is tested in
  // CliQuads and PatchLayout).
  const std::string common = " --grid 8 --quad-length 0.06 --placement random --json";
  auto result = runTool("patches " + q(dir.file("relief.ply")) + " -o " + q(dir.file("a.pds")) + " --png " +
                        q(dir.file("a.png")) + common);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const PatchSet patches = loadPatchSet(dir.file("a.pds"));
  EXPECT_EQ(patches.grid_size, 8);
  EXPECT_NEAR(patches.radius, 0.06 / std::sqrt(2.0), 1e-15);  // unit-cube units
  EXPECT_EQ(static_cast<double>(patches.numPatches()), jsonNumber(result.out, "patches"));
  // 12 patches per patch area at overlap 1 (the relief's area in unit-cube units is ~1.02).
  TriangleMesh unit = mesh;
  UnitCubeNormalization::fromMesh(unit).apply(unit);
  EXPECT_EQ(patches.numPatches(), static_cast<std::size_t>(std::ceil(12.0 * unit.surfaceArea() / (0.06 * 0.06))));
  EXPECT_GT(patches.observedFraction(), 0.9);  // an open relief: patches at the rim are partly off it
  EXPECT_NEAR(jsonNumber(result.out, "observed_fraction"), patches.observedFraction(), 1e-12);
  for (const auto& s : patches.seeds)  // seeds on the normalised surface
    EXPECT_LE(s.cwiseAbs().maxCoeff(), 0.5 + 1e-12);
  EXPECT_EQ(test_support::readFile(dir.file("a.png")).substr(1, 3), "PNG");

  // Same seed, same file; another seed, other patches; overlap 0 gives 1/5 of the patches.
  result = runTool("patches " + q(dir.file("relief.ply")) + " -o " + q(dir.file("b.pds")) + common);
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(test_support::readFile(dir.file("a.pds")), test_support::readFile(dir.file("b.pds")));
  result = runTool("patches " + q(dir.file("relief.ply")) + " -o " + q(dir.file("c.pds")) + common + " --seed 2");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(test_support::readFile(dir.file("a.pds")), test_support::readFile(dir.file("c.pds")));
  result = runTool("patches " + q(dir.file("relief.ply")) + " -o " + q(dir.file("d.pds")) + common + " --overlap 0");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NEAR(jsonNumber(result.out, "patches"), patches.numPatches() / 5.0, 2.0);
}

TEST(CliPatches, ReconstructIdentityRoundTripInInputCoordinates)
{
  test_support::TempDir dir;
  const TriangleMesh mesh = relief();
  writeMesh(dir.file("relief.obj"), mesh);
  double psnr[2], rmse[2];
  for (const bool bilinear : {false, true}) {
    const std::string out = dir.file(bilinear ? "bilinear.ply" : "centres.ply");
    const auto result = runTool("reconstruct " + q(dir.file("relief.obj")) + " -o " + q(out) + " --quad-length 0.06 " +
                                "--rule " + (bilinear ? "bilinear" : "bin-centres") + " --json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    psnr[bilinear] = jsonNumber(result.out, "psnr_db");
    rmse[bilinear] = jsonNumber(result.out, "vertex_rmse");
    TriangleMesh back;
    readMesh(out, back);
    ASSERT_EQ(back.vertices.size(), mesh.vertices.size());
    EXPECT_EQ(back.faces, mesh.faces);
    // The output is in the input's coordinates: normalised with the input's transform, it has
    // the vertex RMSE the tool reported in unit-cube units.
    const UnitCubeNormalization unit = UnitCubeNormalization::fromMesh(mesh);
    TriangleMesh ref = mesh;
    unit.apply(ref);
    unit.apply(back);
    EXPECT_NEAR(vertexRMSE(ref, back), rmse[bilinear], 1e-3 * rmse[bilinear]);
    EXPECT_EQ(jsonNumber(result.out, "vertices_unchanged"), 0.0);
  }
  std::printf("relief identity round trip (L = 0.06, N = 16): bin centres %.1f dB, RMSE %.3e; bilinear %.1f dB, "
              "RMSE %.3e\n", psnr[0], rmse[0], psnr[1], rmse[1]);
  // Quad placement (default). Measured: bin centres 70.2 dB (rim vertices whose bin is off the
  // surface get their 1-ring's mean), bilinear 85.4 dB.
  EXPECT_GT(psnr[0], 65.0);
  EXPECT_GT(psnr[1], 80.0);
  EXPECT_LT(rmse[1], 0.9 * rmse[0]);  // bilinear heights do not quantise to bin centres
}

TEST(CliPatches, ReconstructThroughADictionary)
{
  test_support::TempDir dir;
  writeMesh(dir.file("relief.ply"), relief());
  const std::string in = q(dir.file("relief.ply"));
  auto result = runTool("patches " + in + " -o " + q(dir.file("p.pds")) + " --grid 8 --quad-length 0.06 --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  result = runTool("learn " + q(dir.file("p.pds")) + " -o " + q(dir.file("d.pdd")) +
                   " --atoms 20 --sparsity 3 --iterations 5 --quiet");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  result = runTool("reconstruct " + in + " -o " + q(dir.file("identity.ply")) + " --grid 8 --quad-length 0.06 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const double identity_psnr = jsonNumber(result.out, "psnr_db");
  double previous = 0.0;
  for (const int sparsity : {1, 3}) {
    result = runTool("reconstruct " + in + " -o " + q(dir.file("coded.ply")) + " --grid 8 --quad-length 0.06 --dict " +
                     q(dir.file("d.pdd")) + " --sparsity " + std::to_string(sparsity) + " --json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const double coded_psnr = jsonNumber(result.out, "psnr_db");
    std::printf("relief through a 20-atom dictionary, %d atoms per patch: %.1f dB (identity %.1f dB), patch RMSE %.3e\n",
                sparsity, coded_psnr, identity_psnr, jsonNumber(result.out, "patch_rmse"));
    EXPECT_EQ(jsonNumber(result.out, "atoms"), 20.0);
    EXPECT_GT(jsonNumber(result.out, "patch_rmse"), 0.0);
    EXPECT_LT(coded_psnr, identity_psnr);  // coding loses something ...
    if (sparsity > 1) {
      EXPECT_GT(coded_psnr, previous);  // ... less with more atoms per patch
    }
    EXPECT_GT(coded_psnr, 50.0);
    previous = coded_psnr;
  }
  // A dictionary of another grid size is refused with one line.
  result = runTool("reconstruct " + in + " -o " + q(dir.file("bad.ply")) + " --dict " + q(dir.file("d.pdd")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_TRUE(test_support::readFile(dir.file("bad.ply")).empty());
}

TEST(CliPatches, PatchesOfACloudGoThroughItsPoissonSurface)
{
  test_support::TempDir dir;
  writeSphereCloud(dir.file("cloud.ply"), 4);
  const auto result = runTool("patches " + q(dir.file("cloud.ply")) + " -o " + q(dir.file("c.pds")) +
                              " --grid 8 --quad-length 0.1 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("\"input_kind\": \"cloud\""), std::string::npos);
  // The automatic depth is clamped to [5, 10] (CoarseMeshEstimation).
  EXPECT_GE(jsonNumber(result.out, "poisson_depth"), 5.0);
  EXPECT_LE(jsonNumber(result.out, "poisson_depth"), 10.0);
  const PatchSet patches = loadPatchSet(dir.file("c.pds"));
  EXPECT_GT(patches.numPatches(), 100u);
  // Binned points, not exact heights: most bins see no point of this sparse cloud (2562 points;
  // measured 12.7 % observed).
  std::printf("cloud patches: %.1f %% of bins observed\n", 100.0 * patches.observedFraction());
  EXPECT_GT(patches.observedFraction(), 0.06);
  EXPECT_LT(patches.observedFraction(), 0.5);
}

TEST(CliPatches, ErrorsAndUsage)
{
  test_support::TempDir dir;
  writeMesh(dir.file("relief.ply"), relief());
  const std::string in = dir.file("relief.ply");
  const std::string before = test_support::readFile(in);
  // The output may not be the input (exit 1, one line, the input untouched).
  for (const std::string command : {"patches", "reconstruct"}) {
    auto result = runTool(command + " " + q(in) + " -o " + q(in));
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_TRUE(endsWithOneErrorLine(result.err)) << command << ": " << result.err;
    result = runTool(command + " " + q(in) + " -o " + q(dir.path() + "/../" +
                                                       dir.path().substr(dir.path().rfind('/') + 1) + "/relief.ply"));
    EXPECT_EQ(result.exit_code, 1) << command << " (same file by another name)";
    result = runTool(command + " " + q(in));  // no -o
    EXPECT_EQ(result.exit_code, 2) << command;
    result = runTool(command + " " + q(in) + " -o " + q(dir.file("x.out")) + " --grid 65");
    EXPECT_EQ(result.exit_code, 2) << command;
    result = runTool(command + " " + q(in) + " -o " + q(dir.file("x.out")) + " --quad-length -1");
    EXPECT_EQ(result.exit_code, 2) << command;
    result = runTool(command + " " + q(dir.file("missing.ply")) + " -o " + q(dir.file("x.pds")));
    EXPECT_EQ(result.exit_code, 1) << command;
    EXPECT_TRUE(endsWithOneErrorLine(result.err)) << command << ": " << result.err;
  }
  EXPECT_EQ(test_support::readFile(in), before);
  auto result = runTool("reconstruct " + q(in) + " -o " + q(dir.file("o.ply")) + " --rule nearest");
  EXPECT_EQ(result.exit_code, 2);
  result = runTool("reconstruct " + q(in) + " -o " + q(dir.file("o.ply")) + " --sparsity 4");
  EXPECT_EQ(result.exit_code, 2);  // --sparsity without --dict
  result = runTool("patches " + q(in) + " -o " + q(dir.file("p.pds")) + " --png " + q(dir.file("p.pds")));
  EXPECT_EQ(result.exit_code, 2);
}

TEST(CliPatches, ReconstructOfACloudGivesPointsOnItsSurface)
{
  // A sphere's vertices as a face-less PLY: the output is the cloud of the observed bins, which
  // must lie on the sphere (to the binning's error) and cover it.
  test_support::TempDir dir;
  const TriangleMesh cloud = writeSphereCloud(dir.file("sphere_cloud.ply"), 5);
  const auto result = runTool("reconstruct " + q(dir.file("sphere_cloud.ply")) + " -o " + q(dir.file("out.ply")) +
                              " --quad-length 0.08 --grid 8 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  TriangleMesh out;
  readMesh(dir.file("out.ply"), out);
  EXPECT_TRUE(out.faces.empty());
  EXPECT_EQ(static_cast<double>(out.vertices.size()), jsonNumber(result.out, "points_out"));
  ASSERT_GT(out.vertices.size(), cloud.vertices.size() / 4);
  double worst = 0.0;
  for (const auto& p : out.vertices)
    worst = std::max(worst, std::abs(p.norm() - 2.0));
  // A bin's value is the mean height of its points, placed at the bin centre: where the frame is
  // tilted against the sphere (slope s), that is off by up to s × half a bin diagonal, 0.028
  // (input units) here. Measured worst 0.015 with the seeds on the cloud's Poisson surface (the
  // placement `patches` and `learn` use; 5.4e-3 when reconstruct laid them on the smoothed coarse
  // shape directly), mean far smaller.
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(jsonNumber(result.out, "output_to_input_mean"), 0.01);  // unit-cube units, spacing ~0.012
  // Random placement needs a surface to sample: refused for clouds.
  const auto refused = runTool("reconstruct " + q(dir.file("sphere_cloud.ply")) + " -o " + q(dir.file("r.ply")) +
                               " --placement random");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(refused.err)) << refused.err;
}
