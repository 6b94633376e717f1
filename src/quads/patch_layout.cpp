// PatchLayout: the coarse shape, the quads and their frames, stage after stage.
#include <pcl_patchdict/quads/patch_layout.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/pcl/conversions.h>

#include "geometry/point_search.h"

#include <pcl/kdtree/kdtree_flann.h>

#include <chrono>
#include <cmath>
#include <sstream>

namespace pcl {
namespace patchdict {

namespace {

/** Input vertices that no patch reaches (ball of radius L/√2 around the seed, square of side L in
  * its frame) lie where the quad mesh has no faces — open boundaries, the lattice's rare holes —
  * and would otherwise only be guessed from their neighbours. Each gets a seed of its own, greedily
  * in vertex order: Z its vertex normal, X the X of the nearest existing seed carried over by
  * parallel transport. Returns the number of seeds added (their seed_faces are −1). */
std::size_t addCoverageSeeds(const TriangleMesh& surface, double quad_length, PatchLayout& layout)
{
  if (layout.seeds.empty())
    return 0;
  const double radius = quad_length / std::sqrt(2.0);
  const detail::PointSearch vertex_tree(surface.vertices);
  std::vector<char> covered(surface.vertices.size(), 0);
  std::vector<int> indices;
  std::vector<float> distances;
  const std::vector<Eigen::Vector3d> normals = computeVertexNormals(surface);
  const float search_radius = detail::floatSearchRadius(radius);
  const auto cover = [&](const Eigen::Vector3d& seed, const Eigen::Matrix3d& rows) {
    // Widened float search, then the reconstruction's own exact test.
    vertex_tree.within(seed, search_radius, indices, distances);
    for (const int v : indices)
      if (patchContains(seed, rows, radius, surface.vertices[v], normals[v]))
        covered[v] = 1;
  };
  for (std::size_t s = 0; s < layout.seeds.size(); ++s)
    cover(layout.seeds[s], layout.frames[s]);

  const detail::PointSearch seed_tree(layout.seeds);
  std::size_t added = 0;
  for (std::size_t v = 0; v < surface.vertices.size(); ++v) {
    if (covered[v] || normals[v].squaredNorm() == 0.0)  // zero normal: no face uses v
      continue;
    const Eigen::Vector3d& p = surface.vertices[v];
    seed_tree.nearest(p, 1, indices, distances);
    const Eigen::Matrix3d nearest = layout.frames[static_cast<std::size_t>(indices[0])];  // a copy: frames grows below
    const Eigen::Vector3d z = normals[v];
    Eigen::Vector3d x = transportTangent(nearest.row(0).transpose(), nearest.row(2).transpose(), z);
    if (x.squaredNorm() == 0.0)
      x = z.unitOrthogonal();
    Eigen::Matrix3d rows;
    rows.row(0) = x;
    rows.row(1) = z.cross(x);
    rows.row(2) = z;
    layout.seeds.push_back(p);
    layout.frames.push_back(roundToSinglePrecision(rows));  // as the quads' frames (core/local_frame.h)
    layout.seed_faces.push_back(-1);
    cover(p, rows);
    ++added;
  }
  return added;
}

}  // namespace

void computeLayoutQuads(const TriangleMesh& surface, const PatchLayoutParameters& parameters, PatchLayout& out)
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
    coarse.setInputMesh(std::make_shared<const TriangleMesh>(surface));
  }
  coarse.process(out.coarse, &out.coarse_report);
  out.seconds_coarse = since(t);

  t = Clock::now();
  QuadRemesher remesher;
  remesher.setInputMesh(std::make_shared<const TriangleMesh>(out.coarse));
  remesher.setQuadLength(parameters.quad_length);
  remesher.setSeed(parameters.seed);
  remesher.setNumberOfThreads(parameters.num_threads);
  remesher.process(out.quads, &out.quad_report);
  out.seconds_quads = since(t);
  // Fewer faces than a cube has cannot describe a surface: the lattice is coarser than the shape.
  if (out.quads.faces.size() < 6) {
    std::ostringstream message;
    message << "the quad mesh has " << out.quads.faces.size() << " faces (fewer than 6): the quad length "
            << parameters.quad_length << " is too large for this shape (its coarse shape is "
            << out.coarse.boundingBoxDiagonal() << " across)";
    throw Error(message.str());
  }

  out.quad_length = parameters.quad_length;
}

void computePatchLayout(const TriangleMesh& surface, const PatchLayoutParameters& parameters, PatchLayout& out)
{
  computeLayoutQuads(surface, parameters, out);
  reseedPatchLayout(surface, parameters.overlap, out);
}

void reseedPatchLayout(const TriangleMesh& surface, int overlap, PatchLayout& out)
{
  using Clock = std::chrono::steady_clock;
  const auto t = Clock::now();
  computeQuadFrames(out.quads, overlap, out.seeds, out.frames, &out.seed_faces);
  out.mean_seed_shift = 0.0;
  out.coverage_seeds = 0;
  if (!surface.faces.empty()) {
    // The quads lie on the coarse shape, which smoothing moved off the input (Laplacian
    // smoothing shrinks); patches are sampled from the input, so centre them on it.
    const PointToMeshDistance input(surface);
    std::vector<double> shifts(out.seeds.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t s = 0; s < static_cast<std::ptrdiff_t>(out.seeds.size()); ++s) {
      Eigen::Vector3d& seed = out.seeds[static_cast<std::size_t>(s)];
      const Eigen::Vector3d on_surface = input.query(seed).closest_point;
      shifts[static_cast<std::size_t>(s)] = (on_surface - seed).norm();
      seed = on_surface;
    }
    double moved = 0.0;  // summed in seed order: the same for any thread count
    for (double shift : shifts)
      moved += shift;
    out.mean_seed_shift = out.seeds.empty() ? 0.0 : moved / static_cast<double>(out.seeds.size());
    out.coverage_seeds = addCoverageSeeds(surface, out.quad_length, out);
  }
  out.seconds_frames = std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace patchdict
}  // namespace pcl
