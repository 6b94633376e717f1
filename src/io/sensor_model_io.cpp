// The sensor model's text file: one "key values" line per field, every number to 17 digits, so a
// load gives back the same bits (formatSensorModel, parseSensorModel, saveSensorModel, loadSensorModel).
#include <pcl_patchdict/core/atomic_file.h>
#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/io/sensor_model_io.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
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

static SensorModel parseModelText(const std::string& text)
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

SensorModel parseSensorModel(const std::string& text, const std::string& name)
{
  try {
    return parseModelText(text);
  } catch (const Error& e) {
    throw Error(name + ": " + e.what());
  }
}

void saveSensorModel(const std::string& path, const SensorModel& model)
{
  writeFileAtomically(path, formatSensorModel(model));
}

SensorModel loadSensorModel(const std::string& path)
{
  return parseSensorModel(readWholeFile(path), path);
}

}  // namespace patchdict
}  // namespace pcl
