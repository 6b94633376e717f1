// Patch seeds: where the patches of a surface go, with their reference frames, in one call — on the
// field-aligned quads of its coarse shape (the paper's layout) or area-uniform random (a baseline) —
// and the height maps read at them.
#pragma once

#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/patches/height_maps.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/quads/patch_layout.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

enum class SeedPlacement {
  Quads,  ///< the paper's: computePatchLayout (coarse shape, field-aligned quads, frames by traversal)
  Random  ///< area-uniform random seeds, frames from the interpolated normal (a comparison baseline)
};

/** What layPatches did before the layout: for a cloud, its coarse Poisson surface. */
struct PatchPlacementReport {
  bool from_cloud = false;        ///< the surface had no faces
  bool normals_given = false;     ///< a cloud brought its own normals to Poisson
  int poisson_depth = 0;          ///< clouds: the depth of the coarse Poisson surface
  std::size_t surface_faces = 0;  ///< faces the seeds were laid on (the mesh's, or the Poisson surface's)
  double seconds_surface = 0.0;   ///< clouds: the Poisson surface
};

/** \brief Where the patches of a surface go: the one entry point from a surface to seeds and frames
  * (the tool's `patches`, `learn` and `reconstruct`, QuadFrameEstimation, the benches).
  *
  * `surface` is a clean mesh or a cloud (no faces), in the unit cube. The seeds lie on the mesh
  * itself, or on a cloud's coarse Poisson surface (CoarseMeshEstimation's defaults; the cloud's
  * normals when it has one per point). Quads: computePatchLayout there with `parameters` (L, the
  * overlap k, the smoothing, seed, threads): the whole layout — coarse shape, quads, seeds, frames.
  * Random: area-uniform random seeds (seeded, reproducible) with frameFromNormal at the surface
  * normal interpolated from the vertex normals, 12·(1 + 4k)/5 per L² of area — 12 per patch area at
  * k = 1, what random seeds need to leave almost no vertex uncovered (quad seeds do it with 5);
  * only seeds, frames (seed_faces −1) and quad_length are set. Throws Error for a surface without
  * area, too few points for Poisson, or parameters out of range. */
PatchLayout layPatches(const TriangleMesh& surface, const PatchLayoutParameters& parameters,
                       SeedPlacement placement = SeedPlacement::Quads, PatchPlacementReport* report = nullptr);

/** The random placement itself, with an explicit count. */
PatchLayout randomPatchLayout(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed);

/** \brief The height maps of `surface` at the layout's seeds: grid_size² bins, patch side
  * layout.quad_length (radius L/√2). A mesh's are exact (extractMeshHeightMaps); a cloud's are
  * binned from its points (extractCloudHeightMaps, a bin's mean). */
PatchSet extractSurfacePatches(const TriangleMesh& surface, const PatchLayout& layout, int grid_size);

}  // namespace patchdict
}  // namespace pcl
