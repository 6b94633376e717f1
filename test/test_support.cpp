#include "test_support.h"

#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/io/patch_set_io.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
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
  return runToolWith("", arguments);
}

ToolResult runToolWith(const std::string& launcher, const std::string& arguments)
{
  TempDir capture;
  const std::string out_path = capture.file("stdout"), err_path = capture.file("stderr");
  const std::string command = launcher + (launcher.empty() ? "" : " ") + "'" + PCL_PATCHDICT_TOOL + "' " + arguments +
                              " >'" + out_path + "' 2>'" + err_path + "' </dev/null";
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

std::string jsonString(const std::string& json, const std::string& key)
{
  const std::string marker = "\"" + key + "\": \"";
  const std::size_t start = json.find(marker);
  if (start == std::string::npos)
    return "";
  const std::size_t begin = start + marker.size();
  return json.substr(begin, json.find('"', begin) - begin);
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

Eigen::MatrixXd gaussianMatrix(Eigen::Index rows, Eigen::Index cols, std::uint64_t seed)
{
  std::mt19937_64 random(seed);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index i = 0; i < m.size(); ++i)
    m.data()[i] = normal(random);
  return m;
}

void writePatchSet(const std::string& path, std::uint64_t seed, int count)
{
  using pcl::patchdict::ObservationMask;
  using pcl::patchdict::PatchSet;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gaussian;
  PatchSet set;
  set.grid_size = 8;
  set.radius = 0.1;
  set.heights.resize(64, count);
  set.observed = ObservationMask::Constant(64, count, true);
  for (int p = 0; p < count; ++p) {
    set.seeds.emplace_back(gaussian(rng), gaussian(rng), 0.0);
    set.rotations.push_back(Eigen::Matrix3d::Identity());
    set.source.push_back(0);
    const double phase = gaussian(rng), slope = 0.2 * gaussian(rng);
    for (int b = 0; b < 64; ++b)
      set.heights(b, p) = std::sin(phase + 0.7 * (b % 8)) + slope * (b / 8);
    if (p % 5 == 0)
      for (int b = 0; b < 64; b += 7) {
        set.observed(b, p) = false;
        set.heights(b, p) = 0.0;
      }
  }
  savePatchSet(path, set);
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


SyntheticFrame::SyntheticFrame(std::size_t w, std::size_t h, double focal, double x0, double y0)
    : width(w), height(h), f(focal), cx(x0), cy(y0), depth(w * h, std::numeric_limits<double>::infinity()),
      points(w * h, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()))
{
}

void SyntheticFrame::addPlane(const Eigen::Vector3d& normal, double distance)
{
  const Eigen::Vector3d n = normal.normalized();
  for (std::size_t i = 0; i < depth.size(); ++i) {
    const Eigen::Vector3d ray((static_cast<double>(i % width) - cx) / f, (static_cast<double>(i / width) - cy) / f, 1.0);
    const double along = n.dot(ray);
    if (along > 0.0)
      depth[i] = std::min(depth[i], distance / along);
  }
}

void SyntheticFrame::addBox(std::size_t c0, std::size_t c1, std::size_t r0, std::size_t r1, double z)
{
  for (std::size_t r = r0; r < r1; ++r)
    for (std::size_t c = c0; c < c1; ++c)
      depth[r * width + c] = std::min(depth[r * width + c], z);
}

Eigen::Vector3d SyntheticFrame::truePoint(std::size_t i) const
{
  const double z = depth[i];
  return {(static_cast<double>(i % width) - cx) * z / f, (static_cast<double>(i / width) - cy) * z / f, z};
}

void SyntheticFrame::sense(double noise, double step, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t i = 0; i < depth.size(); ++i) {
    if (!std::isfinite(depth[i]))
      continue;
    double z = depth[i] + noise * depth[i] * depth[i] * gauss(rng);
    if (step > 0.0)
      z = 1.0 / (step * std::round(1.0 / (z * step)));
    points[i] = Eigen::Vector3d((static_cast<double>(i % width) - cx) * z / f, (static_cast<double>(i / width) - cy) * z / f, z);
  }
}

void SyntheticFrame::erase(std::size_t c0, std::size_t c1, std::size_t r0, std::size_t r1)
{
  for (std::size_t r = r0; r < r1; ++r)
    for (std::size_t c = c0; c < c1; ++c)
      points[r * width + c].setConstant(std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::size_t> SyntheticFrame::disc(double column, double row, double radius) const
{
  std::vector<std::size_t> inside;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double dc = static_cast<double>(i % width) - column, dr = static_cast<double>(i / width) - row;
    if (dc * dc + dr * dr <= radius * radius)
      inside.push_back(i);
  }
  return inside;
}

void SyntheticFrame::eraseDisc(double column, double row, double radius)
{
  for (const std::size_t i : disc(column, row, radius))
    points[i].setConstant(std::numeric_limits<double>::quiet_NaN());
}

}  // namespace test_support
