// The sensor model of organised frames, estimated once (sensor_model.h; its text file: io/sensor_model_io.h).
#include <pcl_patchdict/cloud/sensor_model.h>
#include <pcl_patchdict/core/error.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <algorithm>
#include <map>
#include <sstream>

namespace pcl {
namespace patchdict {


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

}  // namespace patchdict
}  // namespace pcl
