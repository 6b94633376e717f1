// Helpers shared by the test suites: temporary directories and running the pcl_patchdict tool.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace test_support {

/** A fresh empty directory under the system temp dir, removed when the object dies. */
class TempDir {
public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::string& path() const { return path_; }
  std::string file(const std::string& name) const { return path_ + "/" + name; }

private:
  std::string path_;
};

struct ToolResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/** Runs the built pcl_patchdict tool with the given argument string (shell-quoted by the caller). */
ToolResult runTool(const std::string& arguments);
/** The same, started by `launcher` (e.g. "mpirun -np 2"): "launcher 'tool' arguments". */
ToolResult runToolWith(const std::string& launcher, const std::string& arguments);

/** Whole file as bytes ("" if missing). */
std::string readFile(const std::string& path);
/** Bytes of `raw` deflated at zlib's best compression (the .pdc format-2 baseline in coder tests). */
std::size_t deflatedSize(const std::string& raw);
/** Writes bytes to a file (test fixtures). */
void writeFile(const std::string& path, const std::string& bytes);

/** The number after "key": in a flat part of a JSON object (NaN if absent or null). */
double jsonNumber(const std::string& json, const std::string& key);
/** The string after "key": in a flat part of a JSON object ("" if absent). */
std::string jsonString(const std::string& json, const std::string& key);
/** Exactly one line, ending in a newline. */
bool isOneLine(const std::string& text);
/** Progress lines may precede it, but an error is exactly one line, the last, saying "error:". */
bool endsWithOneErrorLine(const std::string& err);
/** rows × cols standard normal entries drawn with `seed` (mt19937_64, column-major order). */
Eigen::MatrixXd gaussianMatrix(Eigen::Index rows, Eigen::Index cols, std::uint64_t seed);
/** A .pds of `count` 8×8 sinusoidal height maps (phase and tilt drawn from `seed`), every fifth
  * with some bins unobserved: small patch sets for `learn`. */
void writePatchSet(const std::string& path, std::uint64_t seed, int count = 300);
/** The path in single quotes, for runTool's shell command line. */
std::string q(const std::string& path);

/** A synthetic organised depth frame (pinhole camera, row-major pixels): true depths from planes and
  * boxes (the nearest surface wins), then sensed as a structured-light sensor does — Gaussian depth
  * noise of σ = noise·z² and depth quantised in steps of `step` in 1/z — and NaN where erased. */
struct SyntheticFrame {
  SyntheticFrame(std::size_t width, std::size_t height, double f, double cx, double cy);
  std::size_t width, height;
  double f, cx, cy;
  std::vector<double> depth;            ///< truth; +inf where no surface
  std::vector<Eigen::Vector3d> points;  ///< sensed (after sense()); NaN where nothing was measured
  /** The plane n·x = distance (n normalised here). */
  void addPlane(const Eigen::Vector3d& normal, double distance);
  /** A face at depth z facing the camera over columns [c0, c1) and rows [r0, r1). */
  void addBox(std::size_t c0, std::size_t c1, std::size_t r0, std::size_t r1, double z);
  void sense(double noise, double step, unsigned seed);
  void erase(std::size_t c0, std::size_t c1, std::size_t r0, std::size_t r1);
  void eraseDisc(double column, double row, double radius);
  std::vector<std::size_t> disc(double column, double row, double radius) const;
  Eigen::Vector3d truePoint(std::size_t pixel) const;
};

/** Directory of the bundled data (data/) and test fixtures (test/data). */
std::string dataDir();
std::string testDataDir();

}  // namespace test_support
