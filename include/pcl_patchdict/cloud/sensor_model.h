// The sensor behind an organised cloud — a pinhole camera with its depth-noise law, or a spinning
// LiDAR's beams with its range-noise law — estimated once, saved, and reused for the frames after.
#pragma once

#include <pcl_patchdict/cloud/depth_image.h>
#include <pcl_patchdict/cloud/range_image.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** What estimateSensorModel found; a stream of frames from one sensor shares it. */
struct SensorModel {
  enum class Kind { None, Pinhole, Spinning };
  Kind kind = Kind::None;
  std::size_t width = 0, height = 0;
  PinholeCamera camera;              ///< Pinhole
  DepthNoiseModel depth_noise;       ///< Pinhole
  SpinningSensorModel spinning;      ///< Spinning
  RangeNoiseModel range_noise;       ///< Spinning
  /// Why neither model fits, in one line (kind None).
  std::string failure;
};

/** "pinhole", "spinning" or "none". */
const char* sensorKindName(SensorModel::Kind kind);

/** Where a sensor was: x_cloud = R·x_sensor + o (a PCL cloud's sensor_orientation_ and sensor_origin_). */
struct SensorPose {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d o = Eigen::Vector3d::Zero();
  bool isIdentity() const { return R.isIdentity(1e-12) && o.isZero(0.0); }
};

/** The pose a PCL cloud records (any type with sensor_origin_ and sensor_orientation_). */
template <typename Cloud>
SensorPose sensorPoseOf(const Cloud& cloud)
{
  SensorPose pose;
  pose.R = cloud.sensor_orientation_.template cast<double>().normalized().toRotationMatrix();
  pose.o = cloud.sensor_origin_.template head<3>().template cast<double>();
  return pose;
}

/** The frames an organised grid of a sensor of `kind` is looked for in, in order: a pinhole camera's
  * in the cloud's own frame first (as grabbers write it), then in its pose; a spinning sensor's in
  * its pose first (as drivers set it), then in the cloud's own frame. The pose is tried only when it
  * is not the identity. */
std::vector<SensorPose> sensorFrames(const SensorPose& pose, SensorModel::Kind kind);

/** The points in a sensor's frame: Rᵀ·(x − o). */
std::vector<Eigen::Vector3d> toSensorFrame(const std::vector<Eigen::Vector3d>& points, const SensorPose& frame);

/** The sensor of an organised grid of points in the sensor's frame: a pinhole camera when the grid
  * is a pinhole image (makeDepthImage), else a spinning LiDAR when its rows are beams and its columns
  * azimuth steps (fitSpinningSensor), each with its noise law estimated from these points; kind
  * None (and failure) otherwise. */
SensorModel estimateSensorModel(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height);

/** The same for a cloud seen from `pose`, each kind in the frames sensorFrames names for it (the
  * repairs' order); `found`, when given, receives the frame the model was found in. */
SensorModel estimateSensorModel(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                                const SensorPose& pose, SensorPose* found = nullptr);

/** The depth image of an organised grid on a given camera (a stream's model; nothing is fitted):
  * points within max_reprojection pixels of their own pixel, at a depth within 1000× of the median,
  * are measurements. Throws Error when more than 10 % of the finite points are off their rays (a
  * frame of another camera). */
DepthImage depthImageOnCamera(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                              const PinholeCamera& camera, double max_reprojection = 1.5);

}  // namespace patchdict
}  // namespace pcl
