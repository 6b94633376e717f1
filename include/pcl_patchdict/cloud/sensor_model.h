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

/** The sensor of an organised grid of points in the sensor's frame: a pinhole camera when the grid
  * is a pinhole image (makeDepthImage), else a spinning LiDAR when its rows are beams and its columns
  * azimuth steps (fitSpinningSensor), each with its noise law estimated from these points; kind
  * None (and failure) otherwise. */
SensorModel estimateSensorModel(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height);

/** The depth image of an organised grid on a given camera (a stream's model; nothing is fitted):
  * points within max_reprojection pixels of their own pixel, at a depth within 1000× of the median,
  * are measurements. Throws Error when more than 10 % of the finite points are off their rays (a
  * frame of another camera). */
DepthImage depthImageOnCamera(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                              const PinholeCamera& camera, double max_reprojection = 1.5);

/** Writes the model as text (every number to 17 digits: a load gives back the same bits), atomically.
  * Throws Error when the model has no kind or the file cannot be written. */
void saveSensorModel(const SensorModel& model, const std::string& path);
/** Reads a model written by saveSensorModel; Error (one line) for anything else. */
SensorModel loadSensorModel(const std::string& path);
/** The same, from the file's text. */
SensorModel parseSensorModel(const std::string& text);
std::string formatSensorModel(const SensorModel& model);

}  // namespace patchdict
}  // namespace pcl
