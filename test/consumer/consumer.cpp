// A program that finds the installed package: builds an octahedron, runs one algorithm of the
// library on it (vertex normals) and converts it to a pcl::PolygonMesh; then the PCL skin's classes
// on the three point types they are compiled for: the height maps of a plane through
// pcl::Feature's interface, and QuadFrameEstimation configured (its compute needs a real surface).
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict/pcl/height_map_patch_extractor.h>
#include <pcl_patchdict/pcl/patch_histograms.h>
#include <pcl_patchdict/pcl/quad_frame_estimation.h>
#include <pcl_patchdict/pcl/reference_frame.h>
#include <pcl/PolygonMesh.h>
#include <cmath>
#include <iostream>
#include <memory>

namespace {

/** The bins of the one patch (radius 0.1, identity frame) of points at the 16 × 16 bin centres of
  * a level square, and in `observed` how many of them hold the height 0. */
template <typename PointT>
int planeBins(int& observed)
{
  auto cloud = std::make_shared<pcl::PointCloud<PointT>>();
  const double side = std::sqrt(2.0) * 0.1, bin = side / 16.0;
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      PointT p;
      p.x = static_cast<float>((i + 0.5) * bin - side / 2);
      p.y = static_cast<float>((j + 0.5) * bin - side / 2);
      p.z = 0.f;
      cloud->push_back(p);
    }
  auto seed = std::make_shared<pcl::PointCloud<PointT>>();
  seed->push_back((*cloud)[8 * 16 + 8]);
  (*seed)[0].x = (*seed)[0].y = 0.f;
  auto frames = std::make_shared<pcl::PointCloud<pcl::ReferenceFrame>>(
      pcl::patchdict::toReferenceFrames({Eigen::Matrix3d::Identity()}));
  auto extractor = std::make_shared<pcl::patchdict::HeightMapPatchExtractor<PointT>>();
  extractor->setInputReferenceFrames(frames);
  typename pcl::Feature<PointT, pcl::Histogram<256>>::Ptr feature = extractor;
  feature->setInputCloud(seed);
  feature->setSearchSurface(cloud);
  feature->setRadiusSearch(0.1);
  pcl::PointCloud<pcl::Histogram<256>> patches;
  feature->compute(patches);
  observed = 0;
  for (const float height : patches[0].histogram)
    observed += height == 0.f;
  pcl::patchdict::QuadFrameEstimation<PointT> layout;
  layout.setInputCloud(cloud);
  layout.setQuadLength(0.05);
  return static_cast<int>(sizeof(patches[0].histogram) / sizeof(float));
}

}  // namespace

int main()
{
  pcl::patchdict::TriangleMesh octahedron;
  octahedron.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  octahedron.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  octahedron.normals = pcl::patchdict::computeVertexNormals(octahedron);
  pcl::PolygonMesh polygon_mesh;
  pcl::patchdict::toPolygonMesh(octahedron, polygon_mesh);
  std::cout << "faces=" << polygon_mesh.polygons.size() << "\n";
  int observed[3];
  const int bins[3] = {planeBins<pcl::PointXYZ>(observed[0]), planeBins<pcl::PointNormal>(observed[1]),
                       planeBins<pcl::PointXYZRGBNormal>(observed[2])};
  std::cout << "bins=" << bins[0] << ' ' << bins[1] << ' ' << bins[2] << " observed=" << observed[0] << ' '
            << observed[1] << ' ' << observed[2] << "\n";
  return polygon_mesh.polygons.size() == 8 && octahedron.hasNormals() ? 0 : 1;
}
