// Same input and seed → byte-identical output files, run after run and for 1 or 2 threads, for every
// subcommand that writes one (issue 10). Per-patch and per-vertex loops write to their own slots and
// every reduction runs in a fixed order, so there is nothing to bound: the bytes must match.
#include <pcl_patchdict/io/index_io.h>
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "coding/correlations.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <utility>
#include <vector>

using namespace pcl::patchdict;
using test_support::q;
using test_support::runTool;

TEST(CliDeterminism, EveryWritingSubcommandGivesTheSameBytesForAnyThreadCount)
{
  test_support::TempDir dir;
  // A relief (something for the patches to learn) with holes, noise and missing vertices.
  const TriangleMesh truth = makeSinusoidalRelief(48, 48, 0.04, 0.25);
  writeMesh(dir.file("truth.ply"), truth);
  writeMesh(dir.file("holed.ply"), punchHoles(truth, 3, 0.12, 5).mesh);
  writeMesh(dir.file("noisy.ply"), addNormalNoise(truth, 0.004, 6));
  writeIndexFile(dir.file("missing.txt"), pickMissingVertices(truth, 0.2, 7));

  const std::string t = q(dir.file("truth.ply"));
  struct Step {
    std::string arguments;  ///< OUT stands for the output file
    std::string extension;
  };
  const std::vector<Step> steps{
      {"patches " + t + " -o OUT", ".pds"},
      {"learn " + q(dir.file("ref.pds")) + " --atoms 24 --iterations 5 -o OUT", ".pdd"},
      {"learn " + q(dir.file("ref.pds")) + " --atoms 24 --method online -o OUT", ".pdd"},
      {"quads " + t + " -o OUT", ".obj"},
      {"reconstruct " + t + " --dict " + q(dir.file("ref.pdd")) + " -o OUT", ".ply"},
      {"compress " + t + " --dict " + q(dir.file("ref.pdd")) + " --no-eval -o OUT", ".pdc"},
      {"decompress " + q(dir.file("ref.pdc")) + " --dict " + q(dir.file("ref.pdd")) + " -o OUT", ".ply"},
      {"denoise " + q(dir.file("noisy.ply")) + " --dict " + q(dir.file("ref.pdd")) + " -o OUT", ".ply"},
      {"denoise " + q(dir.file("noisy.ply")) + " --self-similar -o OUT", ".ply"},
      {"fill-holes " + q(dir.file("holed.ply")) + " -o OUT", ".ply"},
      {"fill-holes " + q(dir.file("holed.ply")) + " --dict " + q(dir.file("ref.pdd")) + " -o OUT", ".ply"},
      {"fill-missing " + t + " --missing " + q(dir.file("missing.txt")) + " --dict " + q(dir.file("ref.pdd")) + " -o OUT",
       ".ply"},
  };
  for (const Step& step : steps) {
    std::vector<std::string> outputs;
    for (const char* run : {"1", "2", "2b"}) {
      const std::string output = dir.file(std::string("out_") + run + step.extension);
      std::string arguments = step.arguments;
      arguments.replace(arguments.find("OUT"), 3, q(output));
      const std::string threads = std::string(run).substr(0, 1);
      const auto result = runTool(arguments + " --threads " + threads + " --seed 3 --quiet");
      ASSERT_EQ(result.exit_code, 0) << arguments << "\n" << result.err;
      outputs.push_back(test_support::readFile(output));
      ASSERT_FALSE(outputs.back().empty()) << arguments;
    }
    EXPECT_EQ(outputs[0], outputs[1]) << step.arguments << ": 1 and 2 threads differ";
    EXPECT_EQ(outputs[1], outputs[2]) << step.arguments << ": two runs differ";
    // The first outputs of each kind become the inputs of the later steps.
    for (const char* kind : {".pds", ".pdd", ".pdc"})
      if (step.extension == kind && !std::filesystem::exists(dir.file(std::string("ref") + kind)))
        std::filesystem::copy_file(dir.file(std::string("out_1") + kind), dir.file(std::string("ref") + kind));
  }
}

// The AVX-512 and the AVX2 kernels give the same bits (tests in test_correlations.cpp); here through
// the tool, on the commands that code: learning (K-SVD with its masked coding), masked coding of a
// repair, and compression. PCL_PATCHDICT_SIMD picks the kernels; a wrong value is one error line.
TEST(CliDeterminism, TheAvx2AndAvx512KernelsWriteTheSameBytes)
{
  using pcl::patchdict::detail::SimdKernels;
  test_support::TempDir dir;
  const TriangleMesh truth = makeSinusoidalRelief(40, 40, 0.04, 0.25);
  writeMesh(dir.file("truth.ply"), truth);
  writeMesh(dir.file("holed.ply"), punchHoles(truth, 3, 0.12, 5).mesh);
  const auto bad = test_support::runToolWith("env PCL_PATCHDICT_SIMD=sse9", "learn " + q(dir.file("truth.ply")) +
                                                                                " --atoms 16 --iterations 2 -o " +
                                                                                q(dir.file("bad.pdd")));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("PCL_PATCHDICT_SIMD=sse9: expected portable, avx2 or avx512"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.pdd")));
  if (pcl::patchdict::detail::bestSimdKernels() != SimdKernels::Avx512)
    GTEST_SKIP() << "this CPU has no AVX-512: nothing to compare the AVX2 kernels with";
  const std::string t = q(dir.file("truth.ply"));
  const std::vector<std::pair<std::string, std::string>> steps{
      {"learn " + t + " --atoms 24 --iterations 5 -o OUT", ".pdd"},
      {"fill-holes " + q(dir.file("holed.ply")) + " -o OUT", ".ply"},
      {"compress " + t + " --dict " + q(dir.file("avx512.pdd")) + " --no-eval -o OUT", ".pdc"},
  };
  for (const auto& [arguments_template, extension] : steps) {
    std::string outputs[2];
    for (const std::string kernels : {"avx512", "avx2"}) {
      std::string arguments = arguments_template;
      arguments.replace(arguments.find("OUT"), 3, q(dir.file(kernels + extension)));
      const auto result = test_support::runToolWith("env PCL_PATCHDICT_SIMD=" + kernels, arguments + " --quiet");
      ASSERT_EQ(result.exit_code, 0) << arguments << "\n" << result.err;
      outputs[kernels == "avx2"] = test_support::readFile(dir.file(kernels + extension));
      ASSERT_FALSE(outputs[kernels == "avx2"].empty());
    }
    EXPECT_TRUE(outputs[0] == outputs[1]) << arguments_template;
  }
  // The setting is obeyed: the portable loops (no FMA) round differently.
  const auto portable = test_support::runToolWith("env PCL_PATCHDICT_SIMD=portable",
                                                  "learn " + t + " --atoms 24 --iterations 5 --quiet -o " +
                                                      q(dir.file("portable.pdd")));
  ASSERT_EQ(portable.exit_code, 0) << portable.err;
  EXPECT_FALSE(test_support::readFile(dir.file("portable.pdd")) == test_support::readFile(dir.file("avx512.pdd")));
}
