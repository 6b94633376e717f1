// lidar_frame_pipeline OUT.pcd FRAME.pcd [FRAME.pcd …] — a spinning LiDAR's frames (Ouster, Velodyne,
// Hesai) repaired at sensor rate on the sensor's own point type, as a robot's driver node would.
//
// The first frame gives the sensor model (its beams, azimuth steps and range-noise law); every frame
// after is repaired on it, so nothing is fitted twice and a frame of another sensor is refused
// instead of misrepaired. Each frame is denoised along its beams and its dropouts enclosed by one
// surface are filled in place, on their own rays: the grid (beams × azimuth) and every field stay.
// The last repaired frame is written to OUT.pcd; a mapper would then take its finite points.
#define PCL_NO_PRECOMPILE  // our own point type: the library's templates are compiled here for it
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/filters/filter.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <pcl/register_point_struct.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

// An Ouster driver's point, as its PCDs store it: position, intensity (reflectivity) and the beam.
struct EIGEN_ALIGN16 OusterPoint {
  PCL_ADD_POINT4D;
  float intensity;
  std::uint16_t ring;
  PCL_MAKE_ALIGNED_OPERATOR_NEW
};
POINT_CLOUD_REGISTER_POINT_STRUCT(OusterPoint,
                                  (float, x, x)(float, y, y)(float, z, z)(float, intensity, intensity)(std::uint16_t, ring, ring))

int main(int argc, char** argv)
{
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s OUT.pcd FRAME.pcd [FRAME.pcd ...]\n", argv[0]);
    return 2;
  }
  using Repair = pcl::patchdict::GeometricCloudRepair<OusterPoint>;
  try {
    Repair repair;
    repair.setMode(Repair::Mode::DenoiseAndComplete);
    auto repaired = std::make_shared<pcl::PointCloud<OusterPoint>>();
    int frames = 0;
    for (int k = 2; k < argc; ++k) {
      auto frame = std::make_shared<pcl::PointCloud<OusterPoint>>();
      if (pcl::io::loadPCDFile<OusterPoint>(argv[k], *frame) < 0)
        throw std::runtime_error(std::string("cannot read the frame ") + argv[k]);
      repair.setInputCloud(frame);
      const auto start = std::chrono::steady_clock::now();
      try {
        repair.process(*repaired);
      } catch (const pcl::patchdict::Error& e) {  // e.g. a frame of another sensor than the model's
        std::printf("%s: refused: %s\n", argv[k], e.what());
        continue;
      }
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      const auto& report = repair.getReport();
      if (!report.range_image)
        throw std::runtime_error(std::string(argv[k]) + " is no spinning LiDAR's organised frame");
      if (frames++ == 0) {
        // The first frame's model, kept for the frames that follow (saveSensorModel would write it).
        const pcl::patchdict::SensorModel& model = repair.getSensorModel();
        repair.setSensorModel(model);
        std::printf("sensor: %zu beams x %zu columns, range noise %.1f mm at 10 m, range steps of %.1f mm\n",
                    model.spinning.height, model.spinning.width, 1000.0 * model.range_noise.sigma(10.0),
                    1000.0 * model.range_noise.quantum);
      }
      std::printf("%s: %u x %u frame in %.1f ms (model %s): %zu points moved along their rays, %zu dropouts "
                  "filled (%zu pixels), %zu regions left open\n",
                  argv[k], repaired->width, repaired->height, ms, report.sensor_model_given ? "reused" : "estimated",
                  report.range_denoising.moved, report.range_fill.holes_filled, report.range_fill.pixels_filled,
                  report.range_fill.regions - report.range_fill.holes_filled);
    }
    if (frames == 0)
      throw std::runtime_error("no frame was repaired");
    // What a mapper takes: the finite points (the organised frame itself stays as written).
    pcl::PointCloud<OusterPoint> for_map;
    pcl::Indices kept;
    pcl::removeNaNFromPointCloud(*repaired, for_map, kept);
    if (pcl::io::savePCDFileBinaryCompressed(argv[1], *repaired) < 0)
      throw std::runtime_error(std::string("cannot write ") + argv[1]);
    std::printf("%d frames repaired; the last, %zu finite points of %zu -> %s\n", frames, for_map.size(),
                repaired->size(), argv[1]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lidar_frame_pipeline: %s\n", e.what());
    return 1;
  }
}
