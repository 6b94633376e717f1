// `learn` over shards: --shards S in one process, and one shard per rank under mpirun (the same
// bits), bad inputs on one rank stopping every rank with one error line, or skipped by all.
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict/io/patch_set_io.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

using namespace pcl::patchdict;
using test_support::jsonNumber;
using test_support::q;
using test_support::readFile;
using test_support::runTool;
using test_support::runToolWith;
using test_support::writePatchSet;

namespace {

const char* kJob = " --atoms 16 --sparsity 3 --batch 40 --buffer 100 --iterations 2 --json --quiet";

/** mpirun with two ranks, whoever runs the tests (CI runs as root), on any core count. Under the
  * sanitizers, malloc stacks are unwound the slow way, through Open MPI (built without frame
  * pointers), so that scripts/lsan-mpi.supp can name MPI's own leaks; elsewhere the option is
  * ignored. */
std::string mpirun()
{
#ifdef PCL_PATCHDICT_MPIEXEC
  return std::string("ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:fast_unwind_on_malloc=0\" timeout 300 '") + PCL_PATCHDICT_MPIEXEC +
         "' --allow-run-as-root --oversubscribe -np 2";
#else
  return "";
#endif
}

std::size_t linesWith(const std::string& text, const std::string& needle)
{
  std::size_t count = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
    ++count;
  return count;
}

}  // namespace

TEST(CliLearnShards, ShardsInOneProcessSplitTheInputsAndCodeEveryPatch)
{
  test_support::TempDir dir;
  std::string inputs;
  for (int i = 0; i < 3; ++i) {
    writePatchSet(dir.file("s" + std::to_string(i) + ".pds"), 10 + static_cast<std::uint64_t>(i), 150 + 50 * i);
    inputs += " " + q(dir.file("s" + std::to_string(i) + ".pds"));
  }
  auto one = runTool("learn" + inputs + " -o " + q(dir.file("one.pdd")) + kJob);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  auto two = runTool("learn" + inputs + " -o " + q(dir.file("two.pdd")) + kJob + " --shards 2");
  ASSERT_EQ(two.exit_code, 0) << two.err;
  EXPECT_EQ(jsonNumber(two.out, "shards"), 2.0);
  EXPECT_EQ(jsonNumber(two.out, "ranks"), 1.0);
  EXPECT_EQ(jsonNumber(two.out, "patches"), 600.0);
  // Dealt by size: input 3 (250 patches) to shard 1, inputs 2 and 1 (200 + 150) to shard 2; two passes.
  EXPECT_NE(two.out.find("\"patches_coded_per_shard\": [500,700]"), std::string::npos) << two.out;
  const auto d1 = loadPatchDictionary(dir.file("one.pdd"));
  const auto d2 = loadPatchDictionary(dir.file("two.pdd"));
  // Other batches, so another dictionary; both describe these patches within 5 % of their RMS.
  EXPECT_GT((d1->atoms() - d2->atoms()).cwiseAbs().maxCoeff(), 1e-3);
  const PatchSet all = loadPatchSet(dir.file("s2.pds"));
  const auto error = [&](const PatchDictionary& d) {
    const SparseCodingParameters coding{3, 0.0};
    return observedRMSE(d.decode(d.encodeMasked(all.heights, all.observed, coding)), all.heights, all.observed);
  };
  const double e1 = error(*d1), e2 = error(*d2);
  const double rms = std::sqrt(all.heights.squaredNorm() / static_cast<double>(all.heights.size()));
  EXPECT_LT(e1, 0.05 * rms) << e1 << " of " << rms;
  EXPECT_LT(e2, 0.05 * rms) << e2 << " of " << rms;
  // Shards need online learning and at least one patch each per batch.
  EXPECT_EQ(runTool("learn" + inputs + " -o " + q(dir.file("x.pdd")) + kJob + " --shards 41").exit_code, 2);
  EXPECT_EQ(runTool("learn" + inputs + " -o " + q(dir.file("x.pdd")) + kJob + " --shards 2 --method ksvd").exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.pdd")));
}

TEST(CliLearnShards, TwoRanksGiveTheBitsOfTwoShardsInOneProcess)
{
  if (mpirun().empty())
    GTEST_SKIP() << "built without MPI";
  test_support::TempDir dir;
  std::string inputs;
  for (int i = 0; i < 4; ++i) {
    writePatchSet(dir.file("s" + std::to_string(i) + ".pds"), 20 + static_cast<std::uint64_t>(i), 120 + 40 * i);
    inputs += " " + q(dir.file("s" + std::to_string(i) + ".pds"));
  }
  const auto local = runTool("learn" + inputs + " -o " + q(dir.file("local.pdd")) + kJob + " --shards 2");
  ASSERT_EQ(local.exit_code, 0) << local.err;
  const auto ranks = runToolWith(mpirun(), "learn" + inputs + " -o " + q(dir.file("ranks.pdd")) + kJob);
  ASSERT_EQ(ranks.exit_code, 0) << ranks.err;
  EXPECT_EQ(jsonNumber(ranks.out, "ranks"), 2.0);
  EXPECT_EQ(linesWith(ranks.out, "\"command\": \"learn\""), 1u);  // rank 0 alone reports
  EXPECT_EQ(jsonNumber(ranks.out, "batches"), jsonNumber(local.out, "batches"));
  // Dealt by size: 240 + 120 patches to rank 0, 200 + 160 to rank 1; two passes.
  EXPECT_NE(ranks.out.find("\"patches_coded_per_shard\": [720,720]"), std::string::npos) << ranks.out;
  const std::string bytes = readFile(dir.file("ranks.pdd"));
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(bytes, readFile(dir.file("local.pdd")));  // byte for byte: the same sums in the same order
}

TEST(CliLearnShards, ABadInputOnOneRankStopsEveryRankWithOneErrorLine)
{
  if (mpirun().empty())
    GTEST_SKIP() << "built without MPI";
  test_support::TempDir dir;
  // Dealt by size: c to rank 0, then a and the broken b to rank 1 — the error is rank 1's.
  writePatchSet(dir.file("a.pds"), 31, 200);
  test_support::writeFile(dir.file("b.pds"), "not a patch set\n");
  writePatchSet(dir.file("c.pds"), 32, 250);
  const std::string inputs = " " + q(dir.file("a.pds")) + " " + q(dir.file("b.pds")) + " " + q(dir.file("c.pds"));
  auto result = runToolWith(mpirun(), "learn" + inputs + " -o " + q(dir.file("d.pdd")) + kJob);
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.exit_code, 124) << "a rank hung";  // timeout's code
  EXPECT_EQ(linesWith(result.err, "pcl_patchdict learn:"), 1u) << result.err;
  EXPECT_NE(result.err.find("pcl_patchdict learn: error: input 2/3"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("d.pdd")));

  result = runToolWith(mpirun(), "learn" + inputs + " -o " + q(dir.file("d.pdd")) + kJob + " --skip-bad");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonNumber(result.out, "inputs_skipped"), 1.0);
  EXPECT_EQ(jsonNumber(result.out, "patches"), 450.0);
  EXPECT_NE(result.out.find("\"patches_coded_per_shard\": [500,400]"), std::string::npos) << result.out;
  EXPECT_TRUE(std::filesystem::exists(dir.file("d.pdd")));

  // A command-line error every rank meets alike is reported once too.
  result = runToolWith(mpirun(), "learn" + inputs + " -o " + q(dir.file("e.pdd")) + kJob + " --atoms 0");
  EXPECT_NE(result.exit_code, 0);
  EXPECT_EQ(linesWith(result.err, "pcl_patchdict learn:"), 1u) << result.err;
}

TEST(CliLearnShards, StoppedAndResumedShardsGiveTheUninterruptedDictionary)
{
  test_support::TempDir dir;
  std::string inputs;
  for (int i = 0; i < 4; ++i) {
    writePatchSet(dir.file("s" + std::to_string(i) + ".pds"), 40 + static_cast<std::uint64_t>(i), 100 + 30 * i);
    inputs += " " + q(dir.file("s" + std::to_string(i) + ".pds"));
  }
  const std::string job = "learn" + inputs + kJob + " --shards 2";
  const auto whole = runTool(job + " -o " + q(dir.file("whole.pdd")));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  // Stopped after 3 inputs begun (mid-pass), resumed with a checkpoint after every input.
  auto part = runTool(job + " -o " + q(dir.file("part.pdd")) + " --checkpoint " + q(dir.file("c.pdk")) +
                      " --stop-after 3");
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_NE(part.out.find("\"complete\": false"), std::string::npos) << part.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("part.pdd")));
  part = runTool(job + " -o " + q(dir.file("part.pdd")) + " --resume " + q(dir.file("c.pdk")) + " --checkpoint " +
                 q(dir.file("c.pdk")) + " --checkpoint-every 1");
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_GE(jsonNumber(part.out, "checkpoints_written"), 3.0);
  EXPECT_EQ(readFile(dir.file("part.pdd")), readFile(dir.file("whole.pdd")));
  // Another shard count cannot continue it.
  const auto other = runTool("learn" + inputs + kJob + " -o " + q(dir.file("o.pdd")) + " --resume " + q(dir.file("c.pdk")));
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("shard"), std::string::npos) << other.err;

  if (mpirun().empty())
    return;
  // The same stop and resume on two ranks: rank 0 writes the checkpoint, both continue from it.
  auto ranks = runToolWith(mpirun(), "learn" + inputs + kJob + " -o " + q(dir.file("r.pdd")) + " --checkpoint " +
                                         q(dir.file("r.pdk")) + " --stop-after 3");
  ASSERT_EQ(ranks.exit_code, 0) << ranks.err;
  ranks = runToolWith(mpirun(), "learn" + inputs + kJob + " -o " + q(dir.file("r.pdd")) + " --resume " + q(dir.file("r.pdk")));
  ASSERT_EQ(ranks.exit_code, 0) << ranks.err;
  EXPECT_EQ(readFile(dir.file("r.pdd")), readFile(dir.file("whole.pdd")));
}
