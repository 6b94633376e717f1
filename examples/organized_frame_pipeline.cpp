// organized_frame_pipeline IN.pcd OUT.pcd — a robot's depth frame, repaired and consumed as a robot
// pipeline would: fill and denoise in place (GeometricCloudRepair), then PCL's organised normals.
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/features/integral_image_normal.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>  // std::runtime_error, std::exception
#include <string>

namespace {

// IntegralImageNormalEstimation needs the grid: it works on organised clouds only.
std::size_t organisedNormals(const pcl::PointCloud<pcl::PointXYZRGBA>::ConstPtr& cloud)
{
  pcl::IntegralImageNormalEstimation<pcl::PointXYZRGBA, pcl::Normal> estimation;
  estimation.setNormalEstimationMethod(estimation.AVERAGE_3D_GRADIENT);
  estimation.setMaxDepthChangeFactor(0.02f);
  estimation.setNormalSmoothingSize(10.0f);
  estimation.setInputCloud(cloud);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  std::size_t valid = 0;
  for (const auto& n : normals)
    valid += std::isfinite(n.normal_x) ? 1 : 0;
  return valid;
}

}  // namespace

int main(int argc, char** argv)
{
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s IN.pcd OUT.pcd\n", argv[0]);
    return 2;
  }
  try {
    auto frame = std::make_shared<pcl::PointCloud<pcl::PointXYZRGBA>>();
    if (pcl::io::loadPCDFile<pcl::PointXYZRGBA>(argv[1], *frame) < 0)
      throw std::runtime_error(std::string("cannot read the cloud ") + argv[1]);
    if (frame->height < 2)
      throw std::runtime_error(std::string(argv[1]) + " is not an organised frame");

    // Fill the dropouts enclosed by one surface (never the shadows at depth edges) and denoise along
    // the pixels' rays with the sensor's own noise law; width × height stay, so does every colour.
    pcl::patchdict::GeometricCloudRepair<pcl::PointXYZRGBA> repair;
    repair.setInputCloud(frame);
    repair.setMode(pcl::patchdict::GeometricCloudRepair<pcl::PointXYZRGBA>::Mode::DenoiseAndComplete);
    auto repaired = std::make_shared<pcl::PointCloud<pcl::PointXYZRGBA>>();
    repair.process(*repaired);
    const auto& report = repair.getReport();
    if (!report.depth_image)
      throw std::runtime_error("the frame's grid is no pinhole image; nothing organised to do");

    const std::size_t before = organisedNormals(frame), after = organisedNormals(repaired);
    std::printf("%u x %u frame: camera f %.1f, noise %.2f mm at 1 m (z^%.2f); %zu dropouts filled (%zu pixels), "
                "%zu left open at depth edges; normals on %zu pixels before, %zu after\n",
                repaired->width, repaired->height, report.camera.fx, 1000.0 * report.depth_noise.sigma(1.0),
                report.depth_noise.exponent, report.organized_fill.holes_filled, report.organized_fill.pixels_filled,
                report.organized_fill.not_one_surface, before, after);
    if (pcl::io::savePCDFileBinaryCompressed(argv[2], *repaired) < 0)
      throw std::runtime_error(std::string("cannot write ") + argv[2]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "organized_frame_pipeline: error: %s\n", e.what());
    return 1;
  }
}
