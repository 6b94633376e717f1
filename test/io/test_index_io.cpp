#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/index_io.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>

using namespace pcl::patchdict;

TEST(IndexIO, ReadsWhatItWrites)
{
  test_support::TempDir dir;
  const std::vector<int> indices{5, 0, 17, 3};
  writeIndexFile(dir.file("idx.txt"), indices);
  EXPECT_EQ(readIndexFile(dir.file("idx.txt"), 18), indices);
  EXPECT_EQ(test_support::readFile(dir.file("idx.txt")), "5\n0\n17\n3\n");
}

TEST(IndexIO, SkipsBlankLinesCommentsAndWhitespace)
{
  test_support::TempDir dir;
  test_support::writeFile(dir.file("idx.txt"), "# missing vertices\n\n  4 \r\n2\n\n");
  EXPECT_EQ(readIndexFile(dir.file("idx.txt"), 5), (std::vector<int>{4, 2}));
}

TEST(IndexIO, RejectsBadEntriesNamingTheLine)
{
  test_support::TempDir dir;
  const std::vector<std::pair<std::string, std::string>> cases{
      {"1\n2\nx7\n", "line 3"},     {"1\n-2\n", "negative"},       {"1\n10\n", "out of range"},
      {"3\n1\n3\n", "listed twice"}, {"1.5\n", "not an integer"},  {"99999999999999999999\n", "not an integer"},
      {"2 3\n", "not an integer"},
  };
  for (const auto& [content, expected] : cases) {
    test_support::writeFile(dir.file("bad.txt"), content);
    try {
      readIndexFile(dir.file("bad.txt"), 10);
      ADD_FAILURE() << "accepted: " << content;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(expected), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos);
    }
  }
  EXPECT_THROW(readIndexFile(dir.file("missing.txt"), 10), Error);
}

TEST(AtomicFile, ReplacesWholeAndLeavesNoTemporaryFiles)
{
  test_support::TempDir dir;
  const std::string target = dir.file("out.bin");
  writeFileAtomically(target, "first version, longer");
  writeFileAtomically(target, "second");
  EXPECT_EQ(readWholeFile(target), "second");
  std::size_t entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    (void)entry;
    ++entries;
  }
  EXPECT_EQ(entries, 1u);
}

TEST(AtomicFile, FailsClearlyWithoutTouchingAnything)
{
  test_support::TempDir dir;
  EXPECT_THROW(writeFileAtomically(dir.file("no/such/dir/out.bin"), "x"), Error);
  EXPECT_THROW(writeFileAtomically(dir.path(), "x"), Error);  // a directory
  EXPECT_THROW(readWholeFile(dir.file("missing")), Error);
  EXPECT_THROW(readWholeFile(dir.path()), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// An interrupt (Ctrl-C, kill) in the middle of a write: the process still dies of the signal, and
// neither the target nor the temporary file is left. Also an old target stays whole.
TEST(AtomicFileDeathTest, InterruptDuringAWriteLeavesNothingBehind)
{
  ::testing::GTEST_FLAG(death_test_style) = "threadsafe";
  test_support::TempDir dir;
  const std::string target = dir.file("out.txt");
  const auto interruptedWrite = [&](int signal_number) {
    EXPECT_EXIT(
        {
          removeTemporaryFilesOnInterrupt();
          writeFileAtomically(target, [&](const std::string& temporary) {
            test_support::writeFile(temporary, "half of it");
            std::raise(signal_number);
          });
        },
        ::testing::KilledBySignal(signal_number), "");
  };
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    interruptedWrite(signal_number);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path())) << signal_number;
  }
  writeFileAtomically(target, "old");
  interruptedWrite(SIGTERM);
  EXPECT_EQ(test_support::readFile(target), "old");
  std::size_t entries = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    (void)entry;
    ++entries;
  }
  EXPECT_EQ(entries, 1u);
}
