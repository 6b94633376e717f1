// PatchLayout: the coarse shape, the quads and their frames, stage after stage.
#include <pcl_patchdict/patch_layout.h>

#include <pcl_patchdict/error.h>

#include <chrono>
#include <sstream>

namespace pcl {
namespace patchdict {

void computePatchLayout(const TriangleMesh& surface, const PatchLayoutParameters& parameters, PatchLayout& out)
{
  using Clock = std::chrono::steady_clock;
  const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  out = PatchLayout();

  auto t = Clock::now();
  CoarseMeshEstimation coarse;
  coarse.setIterations(parameters.smoothing_iterations);
  coarse.setMethod(parameters.smoothing);
  if (surface.faces.empty() && surface.normals.size() == surface.vertices.size() && !surface.vertices.empty()) {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    toPointCloud(surface, *cloud);
    coarse.setInputCloud(cloud);
  } else if (surface.faces.empty()) {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    toPointCloud(surface, *cloud);
    coarse.setInputCloud(cloud);
  } else {
    coarse.setInputMesh(surface);
  }
  coarse.process(out.coarse, &out.coarse_report);
  out.seconds_coarse = since(t);

  t = Clock::now();
  QuadRemesher remesher;
  remesher.setInputMesh(out.coarse);
  remesher.setQuadLength(parameters.quad_length);
  remesher.setSeed(parameters.seed);
  remesher.setNumberOfThreads(parameters.num_threads);
  remesher.process(out.quads, &out.quad_report);
  out.seconds_quads = since(t);
  // Fewer faces than a cube has cannot describe a surface: the lattice is coarser than the shape.
  if (out.quads.faces.size() < 6) {
    std::ostringstream message;
    message << "the quad mesh has no faces: the quad length " << parameters.quad_length
            << " is too large for this shape (its bounding box is " << out.coarse.boundingBoxDiagonal()
            << " across)";
    throw Error(message.str());
  }

  t = Clock::now();
  QuadFrameEstimation frames;
  frames.setInputQuadMesh(out.quads);
  frames.setOverlap(parameters.overlap);
  frames.compute(out.seeds, out.frames, &out.seed_faces);
  out.seconds_frames = since(t);
}

}  // namespace patchdict
}  // namespace pcl
