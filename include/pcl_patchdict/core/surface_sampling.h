// Area-weighted uniform random sampling of a triangle mesh's surface, seeded and reproducible.
// Each sample remembers the face it lies on (used by the metrics and the patch extractor).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

struct SurfaceSamples {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int32_t> face_ids;
};

/** \brief Draw num_samples points uniformly by area (face chosen with probability ∝ area, then a
  * uniform barycentric point). Same mesh, count and seed → same samples, whatever the thread count.
  * Throws Error if the mesh has no face of positive area. */
SurfaceSamples sampleSurfaceUniform(const TriangleMesh& mesh, std::size_t num_samples, std::uint64_t seed);

}  // namespace patchdict
}  // namespace pcl
