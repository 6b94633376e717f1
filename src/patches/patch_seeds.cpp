#include <pcl_patchdict/patches/patch_seeds.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/core/surface_sampling.h>
#include <pcl_patchdict/core/vertex_normals.h>
#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/pcl/conversions.h>

#include <chrono>
#include <cmath>

namespace pcl {
namespace patchdict {

PatchLayout randomPatchLayout(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed)
{
  const SurfaceSamples samples = sampleSurfaceUniform(mesh, count, seed);
  const std::vector<Eigen::Vector3d> vertex_normals = computeVertexNormals(mesh);
  PatchLayout out;
  out.seeds = samples.points;
  out.frames.reserve(samples.points.size());
  out.seed_faces.assign(samples.points.size(), -1);
  for (std::size_t i = 0; i < samples.points.size(); ++i) {
    const auto face_index = static_cast<std::size_t>(samples.face_ids[i]);
    const Face& face = mesh.faces[face_index];
    const Eigen::Vector3d& a = mesh.vertices[static_cast<std::size_t>(face[0])];
    const Eigen::Vector3d& b = mesh.vertices[static_cast<std::size_t>(face[1])];
    const Eigen::Vector3d& c = mesh.vertices[static_cast<std::size_t>(face[2])];
    // Barycentric coordinates of the sample (faces are drawn with positive area only).
    const Eigen::Vector3d e1 = b - a, e2 = c - a, d = samples.points[i] - a;
    const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const double denominator = d11 * d22 - d12 * d12;
    double u = 0.0, v = 0.0;
    if (denominator > 0.0) {
      u = (d22 * e1.dot(d) - d12 * e2.dot(d)) / denominator;
      v = (d11 * e2.dot(d) - d12 * e1.dot(d)) / denominator;
    }
    // The normal interpolated across the face varies continuously from face to face, so nearby
    // seeds get nearby frames; a face normal would jump at every edge.
    Eigen::Vector3d normal = (1.0 - u - v) * vertex_normals[static_cast<std::size_t>(face[0])] +
                             u * vertex_normals[static_cast<std::size_t>(face[1])] +
                             v * vertex_normals[static_cast<std::size_t>(face[2])];
    if (!(normal.norm() > 1e-12))
      normal = mesh.faceNormal(face_index);
    out.frames.push_back(frameFromNormal(normal.normalized()));
  }
  return out;
}

namespace {

/** A cloud's coarse Poisson surface (CoarseMeshEstimation's defaults), with its normals if it has them. */
TriangleMesh poissonSurface(const TriangleMesh& cloud, PatchPlacementReport& report)
{
  const auto start = std::chrono::steady_clock::now();
  CoarseMeshEstimation coarse;
  if (cloud.hasNormals()) {
    auto points = std::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    toPointCloud(cloud, *points);
    coarse.setInputCloud(points);
  } else {
    auto points = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    toPointCloud(cloud, *points);
    coarse.setInputCloud(points);
  }
  TriangleMesh surface;
  CoarseMeshEstimation::Report coarse_report;
  coarse.process(surface, &coarse_report);
  report.normals_given = !coarse_report.normals_estimated;
  report.poisson_depth = coarse_report.poisson_depth;
  report.seconds_surface = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return surface;
}

PatchLayout randomPlacement(const TriangleMesh& mesh, const PatchLayoutParameters& parameters)
{
  const double area = mesh.surfaceArea();
  if (!(area > 0.0))
    throw Error("the surface has no area to put patches on");
  const double L = parameters.quad_length;
  const double per_patch_area = 12.0 * (1.0 + 4.0 * parameters.overlap) / 5.0;
  const double count = std::ceil(per_patch_area * area / (L * L));
  if (count > 5e7)
    throw Error("the quad length is too small for this surface (" + std::to_string(static_cast<long long>(count)) +
                " patches)");
  PatchLayout layout = randomPatchLayout(mesh, static_cast<std::size_t>(count), parameters.seed);
  layout.quad_length = L;
  return layout;
}

}  // namespace

PatchLayout layPatches(const TriangleMesh& surface, const PatchLayoutParameters& parameters, SeedPlacement placement,
                       PatchPlacementReport* report)
{
  PatchPlacementReport local;
  PatchPlacementReport& r = report ? *report : local;
  r = PatchPlacementReport();
  if (!(parameters.quad_length > 0.0) || !std::isfinite(parameters.quad_length))
    throw Error("the quad length must be a positive number");
  if (parameters.overlap < 0 || parameters.overlap > 16)
    throw Error("the overlap level must be in [0, 16]");
  r.from_cloud = surface.faces.empty();
  if (r.from_cloud && surface.vertices.size() < CoarseMeshEstimation::getMinimumPoints())
    throw Error("the cloud has " + std::to_string(surface.vertices.size()) + " finite points, fewer than " +
                std::to_string(CoarseMeshEstimation::getMinimumPoints()) + " for its coarse surface");
  const TriangleMesh poisson = r.from_cloud ? poissonSurface(surface, r) : TriangleMesh();
  const TriangleMesh& on = r.from_cloud ? poisson : surface;
  r.surface_faces = on.faces.size();
  if (placement == SeedPlacement::Random)
    return randomPlacement(on, parameters);
  PatchLayout layout;
  computePatchLayout(on, parameters, layout);
  return layout;
}

PatchSet extractSurfacePatches(const TriangleMesh& surface, const PatchLayout& layout, int grid_size)
{
  HeightMapParameters parameters;
  parameters.radius = layout.quad_length / std::sqrt(2.0);  // patch side √2·r = L, as in the paper
  parameters.grid_size = grid_size;
  PatchSet patches;
  if (surface.faces.empty())
    extractCloudHeightMaps(surface.vertices, layout.seeds, layout.frames, parameters, patches);
  else
    extractMeshHeightMaps(surface, layout.seeds, layout.frames, parameters, patches);
  return patches;
}

}  // namespace patchdict
}  // namespace pcl
