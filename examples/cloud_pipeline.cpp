// cloud_pipeline IN.pcd OUT.ply — a noisy scan to a watertight mesh: statistical outlier removal →
// patch denoising with oriented normals (GeometricCloudRepair) → Poisson → PLY.
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

#include <cstdio>
#include <memory>
#include <stdexcept>  // std::runtime_error, std::exception
#include <string>

int main(int argc, char** argv)
{
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s IN.pcd OUT.ply\n", argv[0]);
    return 2;
  }
  try {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    if (pcl::io::loadPCDFile<pcl::PointXYZ>(argv[1], *cloud) < 0)
      throw std::runtime_error(std::string("cannot read the cloud ") + argv[1]);

    // 1. Gross outliers: points whose mean distance to their 50 neighbours is above mean + 1 σ.
    auto filtered = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
    sor.setInputCloud(cloud);
    sor.setMeanK(50);
    sor.setStddevMulThresh(1.0);
    sor.filter(*filtered);

    // 2. Noise: each point moves onto its local height-field patch; PointNormal out: oriented normals.
    pcl::patchdict::GeometricCloudRepair<pcl::PointXYZ, pcl::PointNormal> denoiser;
    denoiser.setInputCloud(filtered);
    denoiser.setOutlierFilter(false);  // the SOR above did it
    auto denoised = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    denoiser.process(*denoised);

    // 3. Surface: Poisson reconstruction at octree depth 8 (needs the oriented normals).
    pcl::Poisson<pcl::PointNormal> poisson;
    poisson.setDepth(8);
    poisson.setInputCloud(denoised);
    pcl::PolygonMesh mesh;
    poisson.reconstruct(mesh);
    if (mesh.polygons.empty())
      throw std::runtime_error("Poisson reconstruction gave no triangles");
    if (pcl::io::savePLYFileBinary(argv[2], mesh) < 0)
      throw std::runtime_error(std::string("cannot write ") + argv[2]);
    const pcl::patchdict::CloudRepairReport& r = denoiser.getReport();
    std::printf("points in %zu, after SOR %zu, out %zu (noise sigma %.3g, bandwidth %.3g); triangles %zu -> %s\n",
                cloud->size(), filtered->size(), r.output_points, r.noise_sigma, r.bandwidth, mesh.polygons.size(), argv[2]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cloud_pipeline: %s\n", e.what());
    return 1;
  }
}
