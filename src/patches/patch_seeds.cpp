#include <pcl_patchdict/patches/patch_seeds.h>

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/quads/patch_layout.h>
#include <pcl_patchdict/core/surface_sampling.h>
#include <pcl_patchdict/core/vertex_normals.h>

#include <cmath>

namespace pcl {
namespace patchdict {

SeedsAndFrames randomSeedsAndFrames(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed)
{
  const SurfaceSamples samples = sampleSurfaceUniform(mesh, count, seed);
  const std::vector<Eigen::Vector3d> vertex_normals = computeVertexNormals(mesh);
  SeedsAndFrames out;
  out.seeds = samples.points;
  out.frames.reserve(samples.points.size());
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

SeedsAndFrames computeSeedsAndFrames(const TriangleMesh& mesh, double quad_length, int overlap, std::uint64_t seed,
                                     SeedPlacement placement)
{
  if (!(quad_length > 0.0) || !std::isfinite(quad_length))
    throw Error("the quad length must be a positive number");
  if (overlap < 0 || overlap > 16)
    throw Error("the overlap level must be in [0, 16]");
  if (placement == SeedPlacement::Quads) {
    PatchLayoutParameters parameters;
    parameters.quad_length = quad_length;
    parameters.overlap = overlap;
    parameters.seed = seed;
    PatchLayout layout;
    computePatchLayout(mesh, parameters, layout);
    SeedsAndFrames out;
    out.seeds = std::move(layout.seeds);
    out.frames = std::move(layout.frames);
    return out;
  }
  const double area = mesh.surfaceArea();
  if (!(area > 0.0))
    throw Error("the surface has no area to put patches on");
  const double per_patch_area = 12.0 * (1.0 + 4.0 * overlap) / 5.0;
  const double count = std::ceil(per_patch_area * area / (quad_length * quad_length));
  if (count > 5e7)
    throw Error("the quad length is too small for this surface (" + std::to_string(static_cast<long long>(count)) +
                " patches)");
  return randomSeedsAndFrames(mesh, static_cast<std::size_t>(count), seed);
}

PatchSet extractMeshPatches(const TriangleMesh& mesh, const SeedsAndFrames& seeds, double quad_length, int grid_size)
{
  HeightMapParameters parameters;
  parameters.radius = quad_length / std::sqrt(2.0);  // patch side √2·r = L, as in the paper
  parameters.grid_size = grid_size;
  PatchSet patches;
  extractMeshHeightMaps(mesh, seeds.seeds, seeds.frames, parameters, patches);
  return patches;
}

}  // namespace patchdict
}  // namespace pcl
