#include "test_support.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace test_support {

TempDir::TempDir()
{
  static std::mt19937_64 rng(static_cast<std::uint64_t>(::getpid()));
  const auto base = std::filesystem::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    const auto candidate = base / ("pcl_patchdict_test_" + std::to_string(rng()));
    if (std::filesystem::create_directory(candidate)) {
      path_ = candidate.string();
      return;
    }
  }
  throw std::runtime_error("cannot create a temporary directory");
}

TempDir::~TempDir()
{
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string readFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return {};
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void writeFile(const std::string& path, const std::string& bytes)
{
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

ToolResult runTool(const std::string& arguments)
{
  TempDir capture;
  const std::string out_path = capture.file("stdout"), err_path = capture.file("stderr");
  const std::string command = std::string("'") + PCL_PATCHDICT_TOOL + "' " + arguments + " >'" + out_path +
                              "' 2>'" + err_path + "' </dev/null";
  const int status = std::system(command.c_str());
  ToolResult result;
  result.exit_code = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  result.out = readFile(out_path);
  result.err = readFile(err_path);
  return result;
}

std::string dataDir() { return PCL_PATCHDICT_DATA_DIR; }
std::string testDataDir() { return PCL_PATCHDICT_TEST_DATA_DIR; }

}  // namespace test_support
