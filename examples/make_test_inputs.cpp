// Test-only input generator for the example tests (not one of the examples):
//   make_test_inputs cloud MESH OUT.pcd   20 000 points sampled on MESH, Gaussian noise, 1 % outliers
//   make_test_inputs holes MESH OUT.ply   MESH with 4 round holes punched (radius 2 % of the diagonal)
// Both seeded: the same files on every run.
#include <pcl_patchdict_eval/mesh_damage.h>
#include <pcl_patchdict/io/mesh_io.h>
#include <pcl_patchdict/core/surface_sampling.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <exception>
#include <random>
#include <stdexcept>
#include <string>

int main(int argc, char** argv)
{
  const std::string mode = argc == 4 ? argv[1] : "";
  if (mode != "cloud" && mode != "holes") {
    std::fprintf(stderr, "usage: %s cloud|holes MESH OUT\n", argv[0]);
    return 2;
  }
  try {
    using namespace pcl::patchdict;
    TriangleMesh mesh;
    readMesh(argv[2], mesh);
    const double diagonal = mesh.boundingBoxDiagonal();
    if (mode == "holes") {
      const HoledMesh holed = punchHoles(mesh, 4, 0.02 * diagonal, 7);
      writeMesh(argv[3], holed.mesh);
      std::printf("%zu holes punched, %zu faces -> %s\n", holed.centres.size(), holed.mesh.numFaces(), argv[3]);
      return 0;
    }
    const SurfaceSamples samples = sampleSurfaceUniform(mesh, 20000, 3);
    std::mt19937_64 rng(5);
    std::normal_distribution<double> noise(0.0, 0.3 * mesh.meanEdgeLength());
    Eigen::Vector3d lo, hi;
    mesh.boundingBox(lo, hi);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    pcl::PointCloud<pcl::PointXYZ> cloud;
    for (std::size_t i = 0; i < samples.points.size(); ++i) {
      Eigen::Vector3d p = samples.points[i] + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      if (i % 100 == 99)  // an outlier anywhere in the bounding box
        p = lo + Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(hi - lo);
      cloud.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
    }
    if (pcl::io::savePCDFileBinary(argv[3], cloud) < 0)
      throw std::runtime_error(std::string("cannot write ") + argv[3]);
    std::printf("%zu points -> %s\n", cloud.size(), argv[3]);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "make_test_inputs: %s\n", e.what());
    return 1;
  }
}
