#include "test_support.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

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

// The number after "key": in a flat part of a JSON object (NaN if absent or null).
double jsonNumber(const std::string& json, const std::string& key)
{
  const std::string needle = "\"" + key + "\": ";
  const auto at = json.find(needle);
  if (at == std::string::npos)
    return std::nan("");
  const char* start = json.c_str() + at + needle.size();
  char* end = nullptr;
  const double value = std::strtod(start, &end);
  return end == start ? std::nan("") : value;
}

bool isOneLine(const std::string& text)
{
  return !text.empty() && std::count(text.begin(), text.end(), '\n') == 1 && text.back() == '\n';
}

// Progress lines may precede it, but an error is exactly one line, the last, saying "error:".
bool endsWithOneErrorLine(const std::string& err)
{
  if (err.empty() || err.back() != '\n')
    return false;
  std::size_t error_lines = 0, start = 0;
  std::string last;
  while (start < err.size()) {
    const auto end = err.find('\n', start);
    last = err.substr(start, end - start);
    error_lines += last.find("error:") != std::string::npos;
    start = end + 1;
  }
  return error_lines == 1 && last.find("error:") != std::string::npos;
}

std::string q(const std::string& path) { return "'" + path + "'"; }

std::size_t deflatedSize(const std::string& raw)
{
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::string packed(size, '\0');
  compress2(reinterpret_cast<Bytef*>(&packed[0]), &size, reinterpret_cast<const Bytef*>(raw.data()),
            static_cast<uLong>(raw.size()), Z_BEST_COMPRESSION);
  return size;
}


}  // namespace test_support
