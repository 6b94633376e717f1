// The sensor model's text file: kind, grid, camera or beams, noise law, every number to 17 digits
// (a load gives back the same bits): what the tool's `--save-sensor-model` writes and `--sensor-model` reads.
#pragma once

#include <pcl_patchdict/cloud/sensor_model.h>

#include <string>

namespace pcl {
namespace patchdict {

/** Writes the model as text (every number to 17 digits: a load gives back the same bits), atomically.
  * Throws Error when the model has no kind or the file cannot be written. */
void saveSensorModel(const std::string& path, const SensorModel& model);
/** Reads a model written by saveSensorModel; Error (one line, naming the file) for anything else. */
SensorModel loadSensorModel(const std::string& path);
/** The same, from the file's text; `name` (a file's, say) starts every error line. */
SensorModel parseSensorModel(const std::string& text, const std::string& name = "<memory>");
/** The file's text (what saveSensorModel writes). Throws Error when the model has no kind. */
std::string formatSensorModel(const SensorModel& model);

}  // namespace patchdict
}  // namespace pcl
