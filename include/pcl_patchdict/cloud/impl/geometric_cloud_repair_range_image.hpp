// GeometricCloudRepair<PointInT, PointOutT>: the spinning-LiDAR path (processRangeImage) and the
// frames processed on a given sensor model (see geometric_cloud_repair.h).
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>

#include <omp.h>
#include <utility>

namespace pcl {
namespace patchdict {
namespace detail {

/** A pixel's normal from the grid (central differences of the present neighbours, the azimuth
  * wrapping), facing its beam's origin. */
inline Eigen::Vector3d rangeGridNormal(const DepthRun& run, const RangeImage& image, std::size_t i)
{
  const std::size_t W = run.W, H = run.H, c = i % W, b = i / W;
  const bool wraps = image.model.wraps;
  const auto at = [&](std::size_t cc, std::size_t bb) {
    return run.present[bb * W + cc] ? run.position[bb * W + cc] : run.position[i];
  };
  const std::size_t left = c > 0 ? c - 1 : wraps ? W - 1 : c, right = c + 1 < W ? c + 1 : wraps ? 0 : c;
  const Eigen::Vector3d du = at(right, b) - at(left, b);
  const Eigen::Vector3d dv = at(c, std::min(H - 1, b + 1)) - at(c, b ? b - 1 : 0);
  Eigen::Vector3d normal = du.cross(dv);
  const Eigen::Vector3d& ray = image.direction(i);
  normal = normal.norm() > 0.0 ? normal.normalized() : Eigen::Vector3d(-ray);
  return normal.dot(ray) > 0.0 ? Eigen::Vector3d(-normal) : normal;
}

/** The median measured range (the report's typical range). */
inline double medianRange(const RangeImage& image)
{
  std::vector<double> ranges;
  for (std::size_t i = 0; i < image.range.size(); ++i)
    if (image.valid[i])
      ranges.push_back(image.range[i]);
  if (ranges.empty())
    return 0.0;
  std::nth_element(ranges.begin(), ranges.begin() + static_cast<std::ptrdiff_t>(ranges.size() / 2), ranges.end());
  return ranges[ranges.size() / 2];
}

}  // namespace detail

template <typename PointInT, typename PointOutT>
bool GeometricCloudRepair<PointInT, PointOutT>::processAsRangeImage(const detail::CloudRun& run,
                                                                        PointCloudOut& output)
{
  const PointCloudIn& input = *input_;
  // The sensor's frame: its pose (sensor_origin_, sensor_orientation_), else the cloud's own.
  std::string failure;
  for (const SensorPose& frame : sensorFrames(sensorPoseOf(input), SensorModel::Kind::Spinning)) {
    const auto start = std::chrono::steady_clock::now();
    const detail::FramedPoints local(run, frame);
    const SpinningSensorModel model = fitSpinningSensor(local.points(), input.width, input.height);
    if (!model.valid && model.rows_are_beams)
      throw Error("the cloud's rows are a spinning LiDAR's beams, but its grid is not one: " + model.failure);
    if (!model.valid) {
      failure = model.failure;
      continue;
    }
    const RangeImage image = makeRangeImage(local.points(), model);
    const RangeNoiseModel noise = estimateRangeNoise(image);
    report_.seconds_sensor_model = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    processRangeImage(local.points(), image, noise, frame.R, frame.o, output);
    return true;
  }
  // A spinning sensor's grid written with its beams as columns would be repaired as something else.
  if (input.width > 1 && input.height > 1) {
    std::vector<Eigen::Vector3d> transposed(run.points.size());
    for (std::size_t r = 0; r < input.height; ++r)
      for (std::size_t c = 0; c < input.width; ++c)
        transposed[c * input.height + r] = run.points[r * input.width + c];
    const SpinningSensorModel model = fitSpinningSensor(transposed, input.height, input.width);
    if (model.valid || model.rows_are_beams)
      throw Error("the cloud's columns are a spinning LiDAR's beams: its grid is transposed (rows must be beams)");
  }
  used_sensor_model_.failure = failure;
  return false;
}

template <typename PointInT, typename PointOutT>
bool GeometricCloudRepair<PointInT, PointOutT>::processOnSensorModel(const detail::CloudRun& run,
                                                                         PointCloudOut& output)
{
  const PointCloudIn& input = *input_;
  const SensorModel& model = sensor_model_;
  if (input.width != model.width || input.height != model.height)
    throw Error("the frame is " + std::to_string(input.width) + " x " + std::to_string(input.height) +
                "; the sensor model given is " + std::to_string(model.width) + " x " + std::to_string(model.height));
  const bool spinning = model.kind == SensorModel::Kind::Spinning;
  // The image on the model in the first of its frames it fits (the error of the last one tried is the
  // one reported); only making the image is tried, the repair runs once, outside.
  const std::vector<SensorPose> frames = sensorFrames(sensorPoseOf(input), model.kind);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const auto start = std::chrono::steady_clock::now();
    const detail::FramedPoints local(run, frames[k]);
    RangeImage range;
    DepthImage depth;
    try {
      if (spinning)
        range = makeRangeImage(local.points(), model.spinning, rays_);
      else
        depth = depthImageOnCamera(local.points(), input.width, input.height, model.camera);
    } catch (const Error&) {
      if (k + 1 == frames.size())
        throw;
      continue;
    }
    report_.seconds_sensor_model = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    report_.sensor_model_given = true;
    if (spinning)
      processRangeImage(local.points(), range, model.range_noise, frames[k].R, frames[k].o, output);
    else
      processDepthImage(local.points(), local.normals(), depth, frames[k].R, frames[k].o, output);
    return true;
  }
  return false;
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::processRangeImage(const std::vector<Eigen::Vector3d>& points,
                                                                      const RangeImage& image,
                                                                      const RangeNoiseModel& noise,
                                                                      const Eigen::Matrix3d& R, const Eigen::Vector3d& o,
                                                                      PointCloudOut& output)
{
  const std::size_t n = image.width * image.height;
  report_.range_image = true;
  report_.spinning = image.model;
  report_.range_noise = noise;
  report_.off_ray_points = image.model.off_ray;
  report_.input_points = n;
  report_.nonfinite_points = n - image.measured();
  used_sensor_model_.kind = SensorModel::Kind::Spinning;
  used_sensor_model_.width = image.width;
  used_sensor_model_.height = image.height;
  used_sensor_model_.spinning = image.model;
  used_sensor_model_.range_noise = noise;
  DepthImage grid;  // the run's bookkeeping: which pixels hold a measurement
  grid.width = image.width;
  grid.height = image.height;
  grid.valid = image.valid;
  grid.depth = image.range;
  detail::DepthRun run(points, grid, pcl::traits::has_normal_v<PointOutT>);
  if (mode_ != Mode::Complete && run.queries.size() < 100)
    throw Error("the frame has " + std::to_string(run.queries.size()) + " measured pixels; denoising needs at least 100");
  const double typical = detail::medianRange(image);
  report_.noise_sigma = noise.sigma(typical);
  report_.mean_spacing = typical * std::abs(image.model.azimuth_step);
  RangeImage current = image;  // the denoised ranges, when denoised first
  if (mode_ != Mode::Complete) {
    RangeDenoisingParameters denoising = range_denoising_;
    if (denoising.num_threads == 0)
      denoising.num_threads = parameters_.num_threads;
    std::vector<double> ranges;
    denoiseRangeImage(image, noise, denoising, ranges, report_.range_denoising);
    report_.seconds_fit = report_.range_denoising.seconds;
    // Each point moves along its own measured ray (from its beam's origin), so that a point whose
    // range is kept keeps its position to the bit.
    for (const std::size_t i : run.queries) {
      current.range[i] = ranges[i];
      if (ranges[i] != image.range[i]) {
        const Eigen::Vector3d& origin = image.rayOrigin(i);
        run.position[i] = origin + (run.measured(i) - origin) * (ranges[i] / image.range[i]);
      }
    }
    report_.bandwidth = denoising.column_radius * report_.mean_spacing;
  }
  if (mode_ != Mode::Denoise) {
    RangeFillParameters fill = range_fill_;
    if (completion_.max_hole_diameter > 0.0)
      fill.max_hole_diameter = completion_.max_hole_diameter;
    std::vector<double> ranges;
    const auto fill_start = std::chrono::steady_clock::now();
    fillRangeImageHoles(current, noise, fill, run.filled, ranges, report_.range_fill);
    report_.completion.seconds_fill = std::chrono::duration<double>(std::chrono::steady_clock::now() - fill_start).count();
    for (std::size_t k = 0; k < run.filled.size(); ++k) {
      const std::size_t i = run.filled[k];
      run.position[i] = image.pointAt(i, ranges[k]);
      run.present[i] = 1;
    }
    report_.points_added = run.filled.size();
    report_.completion.points_added = run.filled.size();
    report_.completion.holes_filled = report_.range_fill.holes_filled;
  }
  if constexpr (pcl::traits::has_normal_v<PointOutT>) {  // normals only for a type that keeps them
    const long long pixels = static_cast<long long>(n);
#pragma omp parallel for schedule(static) num_threads(parameters_.num_threads > 0 ? parameters_.num_threads : omp_get_max_threads())
    for (long long i = 0; i < pixels; ++i)
      if (run.present[std::size_t(i)])
        run.normal[std::size_t(i)] = detail::rangeGridNormal(run, image, std::size_t(i));
  }
  writeDepthOutput(run, R, o, output);
  interpolateFilledIntensity(run, image.model.wraps, output);
}

template <typename PointInT, typename PointOutT>
void GeometricCloudRepair<PointInT, PointOutT>::interpolateFilledIntensity(const detail::DepthRun& run, bool wraps,
                                                                               PointCloudOut& output) const
{
  if constexpr (pcl::traits::has_intensity_v<PointOutT>) {
    std::vector<double> values(run.n);
    for (std::size_t i = 0; i < run.n; ++i)
      values[i] = static_cast<double>(output[i].intensity);
    interpolateAtFilledPixels(values, run.image.valid, run.W, run.H, wraps, run.filled);
    for (const std::size_t i : run.filled)
      output[i].intensity = static_cast<decltype(output[i].intensity)>(values[i]);
  } else {
    (void)run;
    (void)wraps;
    (void)output;
  }
}

}  // namespace patchdict
}  // namespace pcl
