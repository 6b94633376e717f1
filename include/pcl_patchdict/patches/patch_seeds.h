// Patch seeds: where patches go on a (unit-cube) mesh, with their reference frames — on the
// field-aligned quads (the paper's layout) or area-uniform random (a baseline); and their exact height maps.
#pragma once

#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/patches/patch_set.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

struct SeedsAndFrames {
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;  ///< one per seed: rows X, Y, Z, rounded (core/local_frame.h)
};

enum class SeedPlacement {
  Quads,  ///< the paper's: computePatchLayout (coarse shape, field-aligned quads, frames by traversal)
  Random  ///< area-uniform random seeds, frames from the interpolated normal (a comparison baseline)
};

/** Seeds and frames for patches of side `quad_length` (radius quad_length / √2) at overlap level
  * `overlap` (the paper's k: a quad gives its centre and 4k offset seeds).
  * Quads (default): computePatchLayout on the mesh. Random: area-uniform random seeds (seeded,
  * reproducible) with frameFromNormal at the surface normal interpolated from the vertex
  * normals, 12·(1 + 4k)/5 per L² of area — 12 per patch area at k = 1, what random seeds need to
  * leave almost no vertex uncovered (quad seeds do it with 5).
  * Throws Error for a mesh without area or parameters out of range. */
SeedsAndFrames computeSeedsAndFrames(const TriangleMesh& mesh, double quad_length, int overlap, std::uint64_t seed,
                                     SeedPlacement placement = SeedPlacement::Quads);

/** Exact height maps of a (unit-cube) mesh at the given seeds: grid_size² bins, side quad_length. */
PatchSet extractMeshPatches(const TriangleMesh& mesh, const SeedsAndFrames& seeds, double quad_length, int grid_size);

/** The random placement itself, with an explicit count (the demo takes a fixed number). */
SeedsAndFrames randomSeedsAndFrames(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed);

}  // namespace patchdict
}  // namespace pcl
