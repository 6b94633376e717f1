// `pcl_patchdict info CLOUD`: what a cloud user needs to know before repairing it — organisation,
// finite points, spacing, and the sensor of an organised frame: a depth image's camera and noise law
// σ(z) = a·z^p, or a spinning LiDAR's beams and range-noise law (saved with --save-sensor-model).
#include "cli.h"
#include "cloud_input.h"
#include "ring_scan.h"

#include <pcl_patchdict/cloud/depth_image.h>
#include <pcl_patchdict/cloud/gross_outliers.h>
#include <pcl_patchdict/cloud/height_field_hole_filling.h>
#include <pcl_patchdict/cloud/sensor_model.h>
#include <pcl_patchdict/io/sensor_model_io.h>

#include <pcl/kdtree/kdtree_flann.h>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace pcl {
namespace patchdict {
namespace cli {

namespace {

// Median distance to the nearest other point over up to 20000 evenly spaced finite points.
double medianSpacing(const pcl::PointCloud<pcl::PointNormal>::Ptr& cloud)
{
  auto finite = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  for (const auto& p : *cloud)
    if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
      finite->push_back(p);
  if (finite->size() < 2)
    return 0.0;
  pcl::KdTreeFLANN<pcl::PointNormal> tree;
  tree.setInputCloud(finite);
  std::vector<double> nearest;
  pcl::Indices found;
  std::vector<float> squared;
  const std::size_t stride = std::max<std::size_t>(1, finite->size() / 20000);
  for (std::size_t i = 0; i < finite->size(); i += stride)
    if (tree.nearestKSearch((*finite)[i], 2, found, squared) == 2)
      nearest.push_back(std::sqrt(static_cast<double>(squared[1])));
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2), nearest.end());
  return nearest[nearest.size() / 2];
}

// A spinning LiDAR's beams and range noise: the summary lines, and the JSON.
std::string describeSpinning(const SensorModel& model, JsonObject& json)
{
  const SpinningSensorModel& s = model.spinning;
  const RangeNoiseModel& law = model.range_noise;
  const double deg = 180.0 / 3.14159265358979323846;
  JsonObject sensor, noise;
  std::vector<double> elevations;
  for (const double e : s.elevation)
    elevations.push_back(e * deg);
  sensor.add("kind", "spinning").add("beams", s.height).add("columns", s.width)
      .add("elevation_top_degrees", elevations.front()).add("elevation_bottom_degrees", elevations.back())
      .add("azimuth_step_degrees", s.azimuth_step * deg).add("wraps", s.wraps)
      .add("beam_origin_radius", s.beam_radius).add("beam_origin_height", s.beam_height)
      .add("rms_degrees", s.rms_radians * deg).add("off_ray_points", s.off_ray).add("elevations_degrees", elevations);
  noise.add("coefficient", law.coefficient).add("exponent", law.exponent).add("exponent_fitted", law.exponent_fitted)
      .add("quantum", law.quantum).add("samples", law.samples).add("range_low", law.range_low)
      .add("range_high", law.range_high).add("sigma_at_range_low", law.sigma(law.range_low))
      .add("sigma_at_range_high", law.sigma(law.range_high));
  json.add("sensor", sensor).add("range_noise", noise);
  char line[600];
  std::snprintf(line, sizeof line,
                "\n  spinning LiDAR: %zu beams from %.2f to %.2f degrees, %zu columns of %.4f degrees%s; beam origins "
                "%.4g from the axis, %.4g above the origin; rays fit to %.4f degrees RMS, %zu points off their rays"
                "\n  range %.3g to %.3g (5th-95th percentile): noise %.3g to %.3g (sigma = %.3g r^%.2f, %s; "
                "range steps of %.3g)",
                s.height, elevations.front(), elevations.back(), s.width, s.azimuth_step * deg,
                s.wraps ? ", a whole turn" : "", s.beam_radius, s.beam_height, s.rms_radians * deg, s.off_ray,
                law.range_low, law.range_high, law.sigma(law.range_low), law.sigma(law.range_high), law.coefficient,
                law.exponent, law.exponent_fitted ? "exponent fitted" : "exponent 0 assumed", law.quantum);
  return line;
}

}  // namespace

int runCloudInfo(const Arguments& args)
{
  const std::string path = args.positionals()[0];
  const CloudInput input = loadCloudInput(path);
  const auto& cloud = *input.cloud;
  std::vector<Eigen::Vector3d> points(cloud.size());
  std::size_t finite = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    points[i] = Eigen::Vector3d(cloud[i].x, cloud[i].y, cloud[i].z);
    finite += points[i].allFinite() ? 1 : 0;
  }
  const std::vector<std::size_t> first = firstCopies(points);
  std::size_t copies = 0;
  for (std::size_t i = 0; i < first.size(); ++i)
    copies += first[i] != i ? 1 : 0;
  const bool organised = cloud.height > 1;
  RingScan ring_scan;
  const bool by_ring = !organised && readRingScan(input, ring_scan);
  // The sensor, looked for in the frames the repairs look in (sensorFrames).
  const SensorModel model = organised ? estimateSensorModel(points, cloud.width, cloud.height, sensorPoseOf(cloud))
                            : by_ring ? estimateSensorModel(ring_scan.sensor_points, ring_scan.grid.width,
                                                            ring_scan.grid.height)
                                      : SensorModel{};
  const PinholeCamera& pinhole = model.camera;
  const DepthNoiseModel& law = model.depth_noise;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const bool height_field = !organised && isHeightFieldCloud(points, &up);
  const double spacing = medianSpacing(input.cloud);
  JsonObject json;
  json.add("command", "info").add("input", path).add("kind", "cloud").add("points", cloud.size())
      .add("finite_points", finite).add("gross_outliers", input.gross_outliers).add("exact_copies", copies)
      .add("organised", organised).add("width", static_cast<std::size_t>(cloud.width))
      .add("height", static_cast<std::size_t>(cloud.height)).add("has_normals", input.has_normals)
      .add("bbox_largest_side", input.scale).add("spacing", spacing);
  JsonObject viewpoint;
  viewpoint.add("x", static_cast<double>(input.origin.x())).add("y", static_cast<double>(input.origin.y()))
      .add("z", static_cast<double>(input.origin.z())).add("qw", static_cast<double>(input.orientation.w()))
      .add("qx", static_cast<double>(input.orientation.x())).add("qy", static_cast<double>(input.orientation.y()))
      .add("qz", static_cast<double>(input.orientation.z()));
  json.add("viewpoint", viewpoint).add("height_field", height_field);
  if (by_ring)
    json.add("ring_grid_points_placed", ring_scan.grid.placed).add("ring_grid_collisions", ring_scan.grid.collisions);
  std::string summary = std::to_string(cloud.size()) + " points, " + std::to_string(finite) + " finite" +
                        (organised ? ", organised " + std::to_string(cloud.width) + " x " + std::to_string(cloud.height)
                                   : ", unorganised") +
                        (input.gross_outliers ? ", " + std::to_string(input.gross_outliers) + " gross outliers" : "") +
                        (copies ? ", " + std::to_string(copies) + " exact copies" : "");
  char line[400];
  std::snprintf(line, sizeof line, "\n  spacing %.4g (median nearest neighbour)%s", spacing,
                height_field ? ", 2.5-D (a height field over its dominant plane)" : "");
  summary += line;
  if (pinhole.valid) {
    JsonObject camera, noise;
    camera.add("fx", pinhole.fx).add("fy", pinhole.fy).add("cx", pinhole.cx).add("cy", pinhole.cy)
        .add("rms_pixels", pinhole.rms_pixels).add("off_ray_points", pinhole.off_ray);
    const double low = law.depth_low, high = law.depth_high;
    noise.add("coefficient", law.coefficient).add("exponent", law.exponent).add("exponent_fitted", law.exponent_fitted)
        .add("samples", law.samples).add("depth_low", low).add("depth_high", high)
        .add("sigma_at_depth_low", law.sigma(low)).add("sigma_at_depth_high", law.sigma(high))
        .add("spacing_at_depth_low", pinhole.pixelSpacing(low))
        .add("spacing_at_depth_high", pinhole.pixelSpacing(high));
    json.add("camera", camera).add("depth_noise", noise);
    std::snprintf(line, sizeof line,
                  "\n  depth image: camera f %.1f x %.1f, centre (%.1f, %.1f), %zu points off their rays"
                  "\n  depth %.3g to %.3g (5th-95th percentile): pixel spacing %.3g to %.3g, noise %.3g to %.3g"
                  " (sigma = %.3g z^%.2f, %s)",
                  pinhole.fx, pinhole.fy, pinhole.cx, pinhole.cy, pinhole.off_ray, low, high,
                  pinhole.pixelSpacing(low), pinhole.pixelSpacing(high), law.sigma(low), law.sigma(high),
                  law.coefficient, law.exponent, law.exponent_fitted ? "exponent fitted" : "exponent 2 assumed");
    summary += line;
  } else if (model.kind == SensorModel::Kind::Spinning) {
    if (by_ring)
      summary += "\n  unorganised, with rings: " + std::to_string(ring_scan.grid.placed) + " points on a " +
                 std::to_string(ring_scan.grid.width) + " x " + std::to_string(ring_scan.grid.height) + " grid (" +
                 std::to_string(ring_scan.grid.collisions) + " sharing a pixel)";
    summary += describeSpinning(model, json);
  } else if (organised) {
    summary += "\n  " + model.failure + ": repaired as an unorganised cloud";
  }
  if (args.has("save-sensor-model")) {
    const std::string out = args.get("save-sensor-model");
    checkOutputPath(out, path);
    if (model.kind == SensorModel::Kind::None)
      throw Error("no sensor model to save: " +
                  (organised || by_ring ? model.failure : std::string("the cloud is not organised and has no rings")));
    saveSensorModel(out, model);
    json.add("sensor_model_file", out);
    summary += "\n  sensor model written to " + out;
  }
  if (args.has("json"))
    std::cout << json.str() << '\n';
  else
    std::cout << path << " (cloud)\n  " << summary << '\n';
  return 0;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
