// Where the CLI puts its patches: seed points and their reference frames on a (unit-cube) mesh.
// One function, so that the quad frames of QuadFrameEstimation can replace its body later.
#pragma once

#include <pcl_patchdict/patch_set.h>
#include <pcl_patchdict/triangle_mesh.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {
namespace cli {

class StageTimer;

struct SeedsAndFrames {
  std::vector<Eigen::Vector3d> seeds;
  pcl::PointCloud<pcl::ReferenceFrame> frames;  ///< one per seed
};

enum class SeedPlacement {
  Quads,  ///< the paper's: computePatchLayout (coarse shape, field-aligned quads, frames by traversal)
  Random  ///< area-uniform random seeds, frames from the interpolated normal (a comparison baseline)
};

/** Seeds and frames for patches of side `quad_length` (radius quad_length / √2) at overlap level
  * `overlap` (the paper's k: a quad gives its centre and 4k offset seeds).
  * Quads (default): computePatchLayout on the mesh. Random: area-uniform random seeds (seeded,
  * reproducible) with referenceFrameFromNormal at the surface normal interpolated from the vertex
  * normals, 12·(1 + 4k)/5 per L² of area — 12 per patch area at k = 1, what random seeds need to
  * leave almost no vertex uncovered (quad seeds do it with 5).
  * Throws Error for a mesh without area or parameters out of range. */
SeedsAndFrames computeSeedsAndFrames(const TriangleMesh& mesh, double quad_length, int overlap, std::uint64_t seed,
                                     SeedPlacement placement = SeedPlacement::Quads);

/** "quads" or "random" (UsageError otherwise). */
SeedPlacement parseSeedPlacement(const std::string& name);

/** Exact height maps of a (unit-cube) mesh at the given seeds: grid_size² bins, side quad_length. */
PatchSet extractMeshPatches(const TriangleMesh& mesh, const SeedsAndFrames& seeds, double quad_length, int grid_size);

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

/** loadMesh, cleanInputMesh, unit-cube normalisation, seeds (on a cloud's coarse Poisson surface),
  * then exact mesh heights or binned cloud points: the `patches` command. `timer` (optional) gets
  * the stages load, coarse_surface, seeds, extract. Throws Error (one line) for a bad surface. */
SurfacePatches surfacePatches(const std::string& path, const SurfacePatchOptions& options, bool quiet,
                              StageTimer* timer = nullptr);

/** The random placement itself, with an explicit count (the demo takes a fixed number). */
SeedsAndFrames randomSeedsAndFrames(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
