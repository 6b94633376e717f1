// libFuzzer target: the sensor model's text reader (parseSensorModel). An accepted model formats to
// text that reads back to the same text (every number to 17 digits, so the same bits).
#include "fuzz_common.h"

#include <pcl_patchdict/io/sensor_model_io.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  pcl::patchdict::SensorModel model;
  try {
    model = pcl::patchdict::parseSensorModel(fuzz::bytesOf(data, size));
  }
  catch (const pcl::patchdict::Error&) {
    return 0;
  }
  try {
    const std::string text = pcl::patchdict::formatSensorModel(model);
    if (pcl::patchdict::formatSensorModel(pcl::patchdict::parseSensorModel(text)) != text)
      fuzz::fail("an accepted sensor model does not read back to the same text");
  }
  catch (const pcl::patchdict::Error&) {
    fuzz::fail("an accepted sensor model cannot be written and read back");
  }
  return 0;
}
