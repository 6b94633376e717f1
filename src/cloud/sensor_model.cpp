// The sensor model of organised frames: estimated once, written and read back as text (sensor_model.h).
#include <pcl_patchdict/cloud/sensor_model.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/atomic_file.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <algorithm>
#include <map>
#include <sstream>

namespace pcl {
namespace patchdict {

namespace {

const char* const kMagic = "pcl_patchdict sensor model 1";

std::string number(double x)
{
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", x);
  return text;
}

// The file's lines as key → values (whitespace-separated numbers or words).
std::map<std::string, std::vector<std::string>> readLines(const std::string& text)
{
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kMagic)
    throw Error("not a sensor model file (its first line is not '" + std::string(kMagic) + "')");
  std::map<std::string, std::vector<std::string>> fields;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key, word;
    if (!(words >> key))
      continue;
    std::vector<std::string>& values = fields[key];
    if (!values.empty())
      throw Error("sensor model: '" + key + "' given twice");
    while (words >> word)
      values.push_back(word);
  }
  return fields;
}

struct Reader {
  const std::map<std::string, std::vector<std::string>>& fields;
  const std::vector<std::string>& get(const std::string& key, std::size_t count) const
  {
    const auto it = fields.find(key);
    if (it == fields.end())
      throw Error("sensor model: '" + key + "' missing");
    if (it->second.size() != count)
      throw Error("sensor model: '" + key + "' has " + std::to_string(it->second.size()) + " values, not " +
                  std::to_string(count));
    return it->second;
  }
  double real(const std::string& key, std::size_t at = 0, std::size_t count = 1) const
  {
    const std::string& word = get(key, count)[at];
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (end != word.c_str() + word.size() || !std::isfinite(x))
      throw Error("sensor model: '" + key + "' is not a finite number: '" + word + "'");
    return x;
  }
  std::size_t count(const std::string& key, std::size_t most) const
  {
    const double x = real(key);
    if (!(x >= 0.0) || x > double(most) || x != std::floor(x))
      throw Error("sensor model: '" + key + "' must be a whole number in [0, " + std::to_string(most) + "]");
    return static_cast<std::size_t>(x);
  }
};

}  // namespace

const char* sensorKindName(SensorModel::Kind kind)
{
  return kind == SensorModel::Kind::Pinhole ? "pinhole" : kind == SensorModel::Kind::Spinning ? "spinning" : "none";
}

std::vector<SensorPose> sensorFrames(const SensorPose& pose, SensorModel::Kind kind)
{
  if (pose.isIdentity())
    return {SensorPose{}};
  return kind == SensorModel::Kind::Spinning ? std::vector<SensorPose>{pose, SensorPose{}}
                                             : std::vector<SensorPose>{SensorPose{}, pose};
}

std::vector<Eigen::Vector3d> toSensorFrame(const std::vector<Eigen::Vector3d>& points, const SensorPose& frame)
{
  std::vector<Eigen::Vector3d> local(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    local[i] = frame.R.transpose() * (points[i] - frame.o);
  return local;
}

SensorModel estimateSensorModel(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height)
{
  return estimateSensorModel(points, width, height, SensorPose{});
}

SensorModel estimateSensorModel(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                                const SensorPose& pose, SensorPose* found)
{
  SensorModel model;
  model.width = width;
  model.height = height;
  const auto inFrame = [&](const SensorPose& frame) {
    return frame.isIdentity() ? points : toSensorFrame(points, frame);
  };
  for (const SensorPose& frame : height > 1 ? sensorFrames(pose, SensorModel::Kind::Pinhole) : std::vector<SensorPose>{}) {
    const std::vector<Eigen::Vector3d> local = inFrame(frame);
    const DepthImage depth = makeDepthImage(local, width, height);
    if (depth.camera.valid) {
      model.kind = SensorModel::Kind::Pinhole;
      model.camera = depth.camera;
      model.depth_noise = estimateDepthNoise(depth);
      if (found)
        *found = frame;
      return model;
    }
  }
  for (const SensorPose& frame : sensorFrames(pose, SensorModel::Kind::Spinning)) {
    const std::vector<Eigen::Vector3d> local = inFrame(frame);
    model.spinning = fitSpinningSensor(local, width, height);
    if (model.spinning.valid) {
      model.kind = SensorModel::Kind::Spinning;
      model.range_noise = estimateRangeNoise(makeRangeImage(local, model.spinning));
      if (found)
        *found = frame;
      return model;
    }
  }
  model.failure = "neither a pinhole image nor a spinning sensor's grid: " + model.spinning.failure;
  return model;
}

DepthImage depthImageOnCamera(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                              const PinholeCamera& camera, double max_reprojection)
{
  if (points.size() != width * height)
    throw Error("the frame's grid is not " + std::to_string(width) + " x " + std::to_string(height));
  DepthImage image;
  image.width = width;
  image.height = height;
  image.camera = camera;
  image.camera.off_ray = 0;
  image.depth.assign(points.size(), std::numeric_limits<double>::quiet_NaN());
  image.valid.assign(points.size(), 0);
  // The typical depth from up to ~4k evenly spaced points in front (a guard against wild depths).
  std::vector<double> depths;
  const std::size_t stride = std::max<std::size_t>(1, points.size() / 4096);
  for (std::size_t i = 0; i < points.size(); i += stride)
    if (points[i].allFinite() && points[i].z() > 0.0)
      depths.push_back(points[i].z());
  for (std::size_t i = 0; depths.empty() && i < points.size(); ++i)
    if (points[i].allFinite() && points[i].z() > 0.0)
      depths.push_back(points[i].z());
  if (depths.empty())
    throw Error("the frame has no point in front of the sensor model's camera");
  std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
  const double typical = depths[depths.size() / 2];
  // Rows in parallel, each with its own tallies, summed in row order: the same bits for any thread count.
  std::vector<double> row_squares(height, 0.0);
  std::vector<std::size_t> row_finite(height, 0), row_off(height, 0);
  const long long rows = static_cast<long long>(height);
#pragma omp parallel for schedule(static)
  for (long long row = 0; row < rows; ++row)
    for (std::size_t c = 0; c < width; ++c) {
      const std::size_t r = static_cast<std::size_t>(row), i = r * width + c;
      const Eigen::Vector3d& p = points[i];
      if (!p.allFinite())
        continue;
      ++row_finite[r];
      const bool in_range = p.z() > typical / 1000.0 && p.z() < typical * 1000.0;
      const Eigen::Vector2d off = in_range ? Eigen::Vector2d(camera.project(p) - Eigen::Vector2d(double(c), double(r)))
                                           : Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
      if (!(off.norm() <= max_reprojection)) {
        ++row_off[r];
        continue;
      }
      row_squares[r] += off.squaredNorm();
      image.depth[i] = p.z();
      image.valid[i] = 1;
    }
  double squares = 0.0;
  std::size_t finite = 0;
  for (std::size_t r = 0; r < height; ++r) {
    squares += row_squares[r];
    finite += row_finite[r];
    image.camera.off_ray += row_off[r];
  }
  if (image.camera.off_ray * 10 > finite)
    throw Error("the frame does not fit the sensor model: " + std::to_string(image.camera.off_ray) + " of " +
                std::to_string(finite) + " points lie off the model camera's rays (a frame of another sensor?)");
  const std::size_t used = finite - image.camera.off_ray;
  image.camera.rms_pixels = used ? std::sqrt(squares / double(used)) : 0.0;
  image.camera.valid = true;
  return image;
}

std::string formatSensorModel(const SensorModel& model)
{
  if (model.kind == SensorModel::Kind::None)
    throw Error("no sensor model to save: " + model.failure);
  std::ostringstream out;
  out << kMagic << "\nkind " << sensorKindName(model.kind) << "\nwidth " << model.width << "\nheight " << model.height
      << "\n";
  if (model.kind == SensorModel::Kind::Pinhole) {
    const PinholeCamera& c = model.camera;
    const DepthNoiseModel& d = model.depth_noise;
    out << "camera " << number(c.fx) << " " << number(c.fy) << " " << number(c.cx) << " " << number(c.cy) << "\n"
        << "depth_noise " << number(d.coefficient) << " " << number(d.exponent) << "\n";
    return out.str();
  }
  const SpinningSensorModel& s = model.spinning;
  out << "azimuth " << number(s.azimuth_start) << " " << number(s.azimuth_step) << "\nwraps " << (s.wraps ? 1 : 0)
      << "\nbeam_origin " << number(s.beam_radius) << " " << number(s.beam_height) << "\nelevation";
  for (const double e : s.elevation)
    out << " " << number(e);
  out << "\nazimuth_offset";
  for (const double a : s.azimuth_offset)
    out << " " << number(a);
  const RangeNoiseModel& r = model.range_noise;
  out << "\nrange_noise " << number(r.coefficient) << " " << number(r.exponent) << " " << number(r.quantum) << "\n";
  return out.str();
}

SensorModel parseSensorModel(const std::string& text)
{
  const auto fields = readLines(text);
  const Reader read{fields};
  SensorModel model;
  const std::string kind = read.get("kind", 1)[0];
  model.width = read.count("width", 1u << 20);
  model.height = read.count("height", 1u << 20);
  if (model.width < 2 || model.height < 1 || model.width * model.height > (std::size_t(1) << 28))
    throw Error("sensor model: a grid of " + std::to_string(model.width) + " x " + std::to_string(model.height));
  if (kind == "pinhole") {
    model.kind = SensorModel::Kind::Pinhole;
    PinholeCamera& c = model.camera;
    c.fx = read.real("camera", 0, 4);
    c.fy = read.real("camera", 1, 4);
    c.cx = read.real("camera", 2, 4);
    c.cy = read.real("camera", 3, 4);
    c.valid = c.fx != 0.0 && c.fy != 0.0;
    model.depth_noise.coefficient = read.real("depth_noise", 0, 2);
    model.depth_noise.exponent = read.real("depth_noise", 1, 2);
    if (!c.valid || model.depth_noise.coefficient < 0.0)
      throw Error("sensor model: a pinhole camera needs fx, fy != 0 and a noise coefficient >= 0");
    return model;
  }
  if (kind != "spinning")
    throw Error("sensor model: kind '" + kind + "' (pinhole or spinning)");
  model.kind = SensorModel::Kind::Spinning;
  SpinningSensorModel& s = model.spinning;
  s.width = model.width;
  s.height = model.height;
  s.azimuth_start = read.real("azimuth", 0, 2);
  s.azimuth_step = read.real("azimuth", 1, 2);
  s.wraps = read.count("wraps", 1) == 1;
  s.beam_radius = read.real("beam_origin", 0, 2);
  s.beam_height = read.real("beam_origin", 1, 2);
  for (std::size_t b = 0; b < s.height; ++b) {
    s.elevation.push_back(read.real("elevation", b, s.height));
    s.azimuth_offset.push_back(read.real("azimuth_offset", b, s.height));
  }
  for (std::size_t b = 0; b + 2 < s.height; ++b)
    if ((s.elevation[b + 1] - s.elevation[b]) * (s.elevation[b + 2] - s.elevation[b + 1]) <= 0.0)
      throw Error("sensor model: the elevations are not strictly monotonic");
  if (!(std::abs(s.azimuth_step) > 0.0) || std::abs(s.azimuth_step) * double(s.width) > 7.0)
    throw Error("sensor model: the azimuth step must be non-zero and its columns at most one turn");
  model.range_noise.coefficient = read.real("range_noise", 0, 3);
  model.range_noise.exponent = read.real("range_noise", 1, 3);
  model.range_noise.quantum = read.real("range_noise", 2, 3);
  if (model.range_noise.coefficient < 0.0 || model.range_noise.quantum < 0.0 || model.range_noise.exponent < 0.0 ||
      model.range_noise.exponent > 3.0)
    throw Error("sensor model: range_noise coefficient and quantum must be >= 0, the exponent in [0, 3]");
  s.valid = true;
  return model;
}

void saveSensorModel(const SensorModel& model, const std::string& path)
{
  writeFileAtomically(path, formatSensorModel(model));
}

SensorModel loadSensorModel(const std::string& path)
{
  const std::string text = readWholeFile(path);
  try {
    return parseSensorModel(text);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
}

}  // namespace patchdict
}  // namespace pcl
