// A surface file → its patch set, as the `patches` command makes it (load, clean, unit cube, seeds
// on the mesh or a cloud's coarse Poisson surface, exact or binned heights); `learn` reuses it.
#pragma once

#include <pcl_patchdict/patches/patch_seeds.h>

#include <Eigen/Core>

#include <cstdint>
#include <string>

namespace pcl {
namespace patchdict {
namespace cli {

class StageTimer;

/** How `patches` and `learn` turn a surface into patches. */
struct SurfacePatchOptions {
  int grid_size = 16;
  double quad_length = 0.03;
  int overlap = 1;
  std::uint64_t seed = 1;
  SeedPlacement placement = SeedPlacement::Quads;
};

/** A surface file's patch set and what was learned on the way (for reports). */
struct SurfacePatches {
  PatchSet patches;
  bool is_cloud = false;
  std::size_t vertices = 0, faces = 0;
  int poisson_depth = 0;        ///< clouds: depth of the coarse Poisson surface
  std::size_t coarse_faces = 0;  ///< clouds: faces of that surface
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< unit-cube normalisation
  double scale = 1.0;
};

/** loadMesh, cleanInputMesh, unit-cube normalisation, then the library's layPatches (seeds on the
  * mesh or on a cloud's coarse Poisson surface) and extractSurfacePatches (exact mesh heights or
  * binned cloud points): the `patches` command. `timer` (optional) gets the stages load, seeds
  * (with a cloud's Poisson surface), extract. Throws Error (one line) for a bad surface. */
SurfacePatches surfacePatches(const std::string& path, const SurfacePatchOptions& options, bool quiet,
                              StageTimer* timer = nullptr);

/** "quads" or "random" (UsageError otherwise). */
SeedPlacement parseSeedPlacement(const std::string& name);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
