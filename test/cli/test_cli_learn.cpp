// `pcl_patchdict learn` at scale: folders, globs and @lists of patch sets and surfaces, streamed
// through online learning in bounded memory, checkpointed and resumed bit for bit; bad inputs.
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_dictionary_io.h>
#include <pcl_patchdict_eval/shapes.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>

using namespace pcl::patchdict;
using test_support::endsWithOneErrorLine;
using test_support::jsonNumber;
using test_support::jsonString;
using test_support::q;
using test_support::readFile;
using test_support::runTool;
using test_support::writePatchSet;

namespace {

const char* kOnline = " --method online --atoms 12 --sparsity 4 --batch 32 --json";

// The folder `dir`/shapes with two surfaces the patch stage must cut: relief.ply and torus.obj.
void writeShapes(const test_support::TempDir& dir)
{
  std::filesystem::create_directory(dir.file("shapes"));
  writeMesh(dir.file("shapes/relief.ply"), makeSinusoidalRelief(40, 40, 0.08, 0.3));
  writeMesh(dir.file("shapes/torus.obj"), makeTorus(48, 24));
}

}  // namespace

TEST(CliLearn, FolderGlobAndListGiveTheSameStream)
{
  test_support::TempDir dir;
  std::filesystem::create_directory(dir.file("sets"));
  for (int i = 0; i < 3; ++i)
    writePatchSet(dir.file("sets/s" + std::to_string(i) + ".pds"), 10 + static_cast<std::uint64_t>(i));
  test_support::writeFile(dir.file("sets/README.txt"), "not an input\n");
  // The list names the files relative to its own folder, in another order, with a comment.
  std::filesystem::create_directory(dir.file("lists"));
  test_support::writeFile(dir.file("lists/inputs.txt"), "# training shapes\n../sets/s0.pds\n\n  ../sets/s1.pds\n"
                                                        "../sets/s2.pds  \n");
  const auto folder = runTool("learn " + q(dir.file("sets")) + " -o " + q(dir.file("folder.pdd")) + kOnline);
  ASSERT_EQ(folder.exit_code, 0) << folder.err;
  EXPECT_EQ(jsonNumber(folder.out, "inputs"), 3.0);
  EXPECT_EQ(jsonNumber(folder.out, "patches"), 900.0);
  EXPECT_EQ(jsonNumber(folder.out, "patches_streamed"), 2700.0);  // 3 passes by default
  EXPECT_EQ(jsonString(folder.out, "method"), "online");
  // The tool expands the pattern itself when the shell did not (quoted here).
  const auto glob = runTool("learn " + q(dir.file("sets/s*.pds")) + " -o " + q(dir.file("glob.pdd")) + kOnline);
  ASSERT_EQ(glob.exit_code, 0) << glob.err;
  EXPECT_EQ(jsonNumber(glob.out, "inputs"), 3.0);
  const auto list = runTool("learn @" + q(dir.file("lists/inputs.txt")) + " -o " + q(dir.file("list.pdd")) + kOnline);
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_EQ(jsonNumber(list.out, "inputs"), 3.0);
  const std::string reference = readFile(dir.file("folder.pdd"));
  ASSERT_FALSE(reference.empty());
  EXPECT_EQ(readFile(dir.file("glob.pdd")), reference);
  EXPECT_EQ(readFile(dir.file("list.pdd")), reference);
  // Another order is another stream (order matters, so the expansion must be sorted).
  test_support::writeFile(dir.file("lists/reversed.txt"), "../sets/s2.pds\n../sets/s1.pds\n../sets/s0.pds\n");
  const auto reversed =
      runTool("learn @" + q(dir.file("lists/reversed.txt")) + " -o " + q(dir.file("reversed.pdd")) + kOnline);
  ASSERT_EQ(reversed.exit_code, 0) << reversed.err;
  EXPECT_NE(readFile(dir.file("reversed.pdd")), reference);

  // A pattern without match, an empty folder and a list naming nothing: one line each.
  std::filesystem::create_directory(dir.file("empty"));
  for (const std::string& input : {q(dir.file("sets/none*.pds")), q(dir.file("empty")), "@" + q(dir.file("none.txt"))}) {
    const auto bad = runTool("learn " + input + " -o " + q(dir.file("bad.pdd")) + " --quiet");
    EXPECT_EQ(bad.exit_code, 1) << input;
    EXPECT_TRUE(endsWithOneErrorLine(bad.err)) << bad.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("bad.pdd")));
}

TEST(CliLearn, SurfacesGoThroughThePatchStage)
{
  test_support::TempDir dir;
  writeShapes(dir);
  // One surface: a local dictionary, K-SVD, at the requested grid.
  auto result = runTool("learn " + q(dir.file("shapes/relief.ply")) + " -o " + q(dir.file("local.pdd")) +
                        " --grid 8 --quad-length 0.1 --atoms 16 --iterations 3 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonString(result.out, "method"), "ksvd");
  EXPECT_GT(jsonNumber(result.out, "patches"), 30.0);
  const auto local = loadPatchDictionary(dir.file("local.pdd"), 8);
  EXPECT_EQ(local->atoms().rows(), 64);
  EXPECT_EQ(local->atoms().cols(), 16);
  EXPECT_EQ(static_cast<double>(local->trainingPatches()), jsonNumber(result.out, "patches"));
  // The same surface through `patches`: the same patch count (the same stages).
  const auto patches = runTool("patches " + q(dir.file("shapes/relief.ply")) + " -o " + q(dir.file("relief.pds")) +
                               " --grid 8 --quad-length 0.1 --json");
  ASSERT_EQ(patches.exit_code, 0) << patches.err;
  EXPECT_EQ(jsonNumber(patches.out, "patches"), jsonNumber(result.out, "patches"));
  // A folder of surfaces: a global dictionary, online by default.
  result = runTool("learn " + q(dir.file("shapes")) + " -o " + q(dir.file("global.pdd")) +
                   " --grid 8 --quad-length 0.1 --atoms 16 --batch 32 --iterations 2 --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonString(result.out, "method"), "online");
  EXPECT_EQ(jsonNumber(result.out, "inputs"), 2.0);
  EXPECT_EQ(jsonNumber(result.out, "grid_size"), 8.0);
  EXPECT_EQ(loadPatchDictionary(dir.file("global.pdd"), 8)->atoms().cols(), 16);
  // A .pds of another grid among them is refused, naming both grids.
  writePatchSet(dir.file("shapes/zz.pds"), 3);  // 8×8
  result = runTool("learn " + q(dir.file("shapes")) + " -o " + q(dir.file("mixed.pdd")) +
                   " --grid 16 --quad-length 0.1 --atoms 16 --quiet");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_NE(result.err.find("16×16"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("mixed.pdd")));
}

// Surface inputs are patched once: passes 2 and 3 read their patches back from a temporary folder
// (float64, so the very same patches), which is gone when the run ends; --no-patch-cache makes
// them again and must give the same dictionary, byte for byte.
TEST(CliLearn, LaterPassesReadThePatchesBackAndLearnTheSameDictionary)
{
  test_support::TempDir dir;
  writeShapes(dir);
  writePatchSet(dir.file("shapes/zz.pds"), 3);  // a patch set is read as it is, never cached
  // The tool's temporary folder, here (TMPDIR, which std::filesystem::temp_directory_path reads).
  std::filesystem::create_directory(dir.file("tmp"));
  const char* old_tmpdir = std::getenv("TMPDIR");
  const std::string saved = old_tmpdir ? old_tmpdir : "";
  ::setenv("TMPDIR", dir.file("tmp").c_str(), 1);
  const std::string common = " --grid 8 --quad-length 0.1 --atoms 16 --batch 32 --iterations 3 --json";
  const auto cached = runTool("learn " + q(dir.file("shapes")) + " -o " + q(dir.file("cached.pdd")) + common);
  ASSERT_EQ(cached.exit_code, 0) << cached.err;
  EXPECT_EQ(jsonNumber(cached.out, "inputs_read_back"), 4.0);  // 2 surfaces × passes 2 and 3
  EXPECT_GT(jsonNumber(cached.out, "bytes"), 1000.0);
  const auto again = runTool("learn " + q(dir.file("shapes")) + " -o " + q(dir.file("again.pdd")) + common +
                             " --no-patch-cache");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(jsonNumber(again.out, "inputs_read_back"), 0.0);
  EXPECT_EQ(readFile(dir.file("cached.pdd")), readFile(dir.file("again.pdd")));
  EXPECT_TRUE(std::filesystem::is_empty(dir.file("tmp")));  // the cache went with the run
  if (old_tmpdir)
    ::setenv("TMPDIR", saved.c_str(), 1);
  else
    ::unsetenv("TMPDIR");
  // K-SVD holds every patch in memory: the option is refused there.
  const auto ksvd = runTool("learn " + q(dir.file("shapes/relief.ply")) + " -o " + q(dir.file("k.pdd")) +
                            " --no-patch-cache --quiet");
  EXPECT_EQ(ksvd.exit_code, 2);
  EXPECT_TRUE(test_support::isOneLine(ksvd.err)) << ksvd.err;
}

TEST(CliLearn, ResumedRunIsByteIdenticalToAnUninterruptedOne)
{
  test_support::TempDir dir;
  std::filesystem::create_directory(dir.file("in"));
  for (int i = 0; i < 4; ++i)
    writePatchSet(dir.file("in/s" + std::to_string(i) + ".pds"), 20 + static_cast<std::uint64_t>(i), 150 + 40 * i);
  // A small buffer, so that a checkpoint catches patches in it and a partial mini-batch.
  const std::string common = " --buffer 100 --iterations 2 --seed 7" + std::string(kOnline);
  const auto whole = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("whole.pdd")) + common);
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  const std::string checkpoint = q(dir.file("run.pdk"));
  // Three inputs, stop; three more (across the end of pass 1), stop; then the rest.
  auto part = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("resumed.pdd")) + common +
                      " --checkpoint " + checkpoint + " --checkpoint-every 2 --stop-after 3");
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_NE(part.out.find("\"complete\": false"), std::string::npos) << part.out;
  EXPECT_FALSE(std::filesystem::exists(dir.file("resumed.pdd")));  // no dictionary before the end
  EXPECT_EQ(jsonNumber(part.out, "checkpoints_written"), 2.0);
  part = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("resumed.pdd")) + common + " --checkpoint " +
                 checkpoint + " --resume " + checkpoint + " --stop-after 3");
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_EQ(jsonNumber(part.out, "resumed_input"), 3.0);
  EXPECT_FALSE(std::filesystem::exists(dir.file("resumed.pdd")));
  part = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("resumed.pdd")) + common + " --checkpoint " +
                 checkpoint + " --resume " + checkpoint);
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_EQ(jsonNumber(part.out, "resumed_pass"), 1.0);
  EXPECT_EQ(jsonNumber(part.out, "patches"), jsonNumber(whole.out, "patches"));
  EXPECT_EQ(jsonNumber(part.out, "patches_streamed"), jsonNumber(whole.out, "patches_streamed"));
  const std::string expected = readFile(dir.file("whole.pdd"));
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(readFile(dir.file("resumed.pdd")), expected);
  // Resuming from the finished checkpoint writes the same dictionary again.
  part = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("again.pdd")) + common + " --resume " + checkpoint);
  ASSERT_EQ(part.exit_code, 0) << part.err;
  EXPECT_EQ(readFile(dir.file("again.pdd")), expected);
  // Another seed really is another dictionary (the comparison above can fail).
  const auto other = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("other.pdd")) +
                             " --buffer 100 --iterations 2 --seed 8" + kOnline);
  ASSERT_EQ(other.exit_code, 0) << other.err;
  EXPECT_NE(readFile(dir.file("other.pdd")), expected);
}

TEST(CliLearn, ResumeRefusesAnotherJob)
{
  test_support::TempDir dir;
  std::filesystem::create_directory(dir.file("in"));
  for (int i = 0; i < 3; ++i)
    writePatchSet(dir.file("in/s" + std::to_string(i) + ".pds"), 30 + static_cast<std::uint64_t>(i));
  const std::string checkpoint = q(dir.file("run.pdk"));
  auto result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline + " --checkpoint " +
                        checkpoint + " --stop-after 1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  // Another input list: one file fewer.
  result = runTool("learn " + q(dir.file("in/s0.pds")) + " " + q(dir.file("in/s1.pds")) + " -o " +
                   q(dir.file("d.pdd")) + kOnline + " --resume " + checkpoint);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_NE(result.err.find("another input list"), std::string::npos) << result.err;
  // The same files, one of them changed.
  writePatchSet(dir.file("in/s2.pds"), 99, 301);
  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline + " --resume " + checkpoint);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("another input list"), std::string::npos) << result.err;
  writePatchSet(dir.file("in/s2.pds"), 32);
  // Other parameters.
  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline + " --atoms 13 --resume " +
                   checkpoint);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_NE(result.err.find("--atoms 12"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("d.pdd")));
  // A corrupted checkpoint.
  std::string bytes = readFile(dir.file("run.pdk"));
  bytes[bytes.size() / 2] ^= 0x10;
  test_support::writeFile(dir.file("bad.pdk"), bytes);
  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline + " --resume " +
                   q(dir.file("bad.pdk")));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("checksum"), std::string::npos) << result.err;
  // The right job resumes.
  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline + " --resume " + checkpoint);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  // Checkpoints are for online learning only.
  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("k.pdd")) + " --method ksvd --checkpoint " +
                   checkpoint);
  EXPECT_EQ(result.exit_code, 2);
}

TEST(CliLearn, BadInputIsAnErrorOrSkippedAndReported)
{
  test_support::TempDir dir;
  std::filesystem::create_directory(dir.file("in"));
  writePatchSet(dir.file("in/a.pds"), 1);
  test_support::writeFile(dir.file("in/b.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n");  // face index out of range
  writePatchSet(dir.file("in/c.pds"), 2);
  auto result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline);
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
  EXPECT_NE(result.err.find("input 2/3"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("d.pdd")));  // never a half-made dictionary

  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline + " --skip-bad");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonNumber(result.out, "inputs"), 3.0);
  EXPECT_EQ(jsonNumber(result.out, "inputs_skipped"), 1.0);
  EXPECT_EQ(jsonNumber(result.out, "patches"), 600.0);
  EXPECT_NE(result.out.find("\"skipped\": [{\"input\": \"" + dir.file("in/b.obj") + "\", \"reason\": "),
            std::string::npos)
      << result.out;
  EXPECT_TRUE(std::filesystem::exists(dir.file("d.pdd")));
  // K-SVD skips the same way; nothing but bad inputs is still an error.
  result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("k.pdd")) +
                   " --method ksvd --atoms 12 --iterations 2 --skip-bad --json");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonNumber(result.out, "inputs_skipped"), 1.0);
  result = runTool("learn " + q(dir.file("in/b.obj")) + " " + q(dir.file("in/b.obj")) + " -o " +
                   q(dir.file("n.pdd")) + kOnline + " --skip-bad");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_TRUE(endsWithOneErrorLine(result.err)) << result.err;
}

TEST(CliLearn, MemoryIsBoundedByTheBuffer)
{
  test_support::TempDir dir;
  std::filesystem::create_directory(dir.file("in"));
  for (int i = 0; i < 6; ++i)
    writePatchSet(dir.file("in/s" + std::to_string(i) + ".pds"), 40 + static_cast<std::uint64_t>(i));
  const auto result = runTool("learn " + q(dir.file("in")) + " -o " + q(dir.file("d.pdd")) + kOnline +
                              " --buffer 200 --iterations 1");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(jsonNumber(result.out, "patches"), 1800.0);
  EXPECT_EQ(jsonNumber(result.out, "max_input_patches"), 300.0);  // one input in memory at a time
  EXPECT_EQ(jsonNumber(result.out, "max_buffered_patches"), 200.0);
  // Every patch reached the learner: 1800 = 56 batches of 32 + one of 8.
  EXPECT_EQ(jsonNumber(result.out, "batches"), 57.0);
}
