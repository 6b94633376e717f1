// PatchLayout — where the patches of a surface go: coarse shape → field-aligned quad mesh → one
// frame per quad plus overlap seeds (section 3.3 of Sarkar et al. 2017), in one call.
#pragma once

#include <pcl_patchdict/geometry/coarse_mesh_estimation.h>
#include <pcl_patchdict/quads/quad_frames.h>
#include <pcl_patchdict/quads/quad_remesher.h>

#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

struct PatchLayoutParameters {
  double quad_length = 0.03;  ///< L, in the units of the surface given (normalised: unit cube)
  int overlap = 1;            ///< k: 4k offset seeds per quad
  int smoothing_iterations = 30;
  /** Laplacian, the paper's setting, by default: its smoother coarse shape gives more consistent
    * quads and frames than Taubin's (figures in docs/); its shrinking does not matter here, because
    * patches are sampled from the input surface, not from the coarse one. */
  CoarseMeshEstimation::Method smoothing = CoarseMeshEstimation::Method::Laplacian;
  std::uint64_t seed = 0;
  int num_threads = 0;
};

struct PatchLayout {
  TriangleMesh coarse;  ///< the smoothed shape the quads are laid on
  QuadMesh quads;
  std::vector<Eigen::Vector3d> seeds;
  std::vector<Eigen::Matrix3d> frames;   ///< one per seed: rows X, Y, Z, rounded (core/local_frame.h)
  std::vector<std::int32_t> seed_faces;  ///< the quad-mesh face of each seed (−1: coverage seed)
  CoarseMeshEstimation::Report coarse_report;
  QuadRemesher::Report quad_report;
  std::size_t coverage_seeds = 0;  ///< seeds added where no quad's patch reaches (seed_faces −1)
  double mean_seed_shift = 0.0;  ///< mean distance the seeds moved from the quads onto the input
  double quad_length = 0.0;  ///< the L the quads were made at
  double seconds_coarse = 0.0, seconds_quads = 0.0, seconds_frames = 0.0;
};

/** \brief The three stages in a row: CoarseMeshEstimation (a mesh is smoothed; a surface without
  * faces is treated as a point cloud: Poisson, trimming, smoothing), QuadRemesher on the coarse
  * shape, computeQuadFrames on the quads; for a mesh input, the seeds are then moved to their
  * closest points on the input (frames unchanged), so patches are centred on the surface they
  * sample rather than on the smoothed one, and input vertices no patch reaches (open boundaries,
  * the lattice's rare holes) get seeds of their own (see PatchLayout::coverage_seeds). Throws Error from any stage, and when the quad mesh
  * comes out with fewer than 6 faces (L too large for the shape). */
void computePatchLayout(const TriangleMesh& surface, const PatchLayoutParameters& parameters, PatchLayout& out);

/** \brief The first two stages of computePatchLayout alone: the coarse shape and its quads (out.coarse,
  * out.quads, their reports and times, out.quad_length; no seeds). For a caller that derives its seeds
  * from the quads in its own way (the codec: from the quad mesh it stores, so that its decoder can).
  * Throws Error as computePatchLayout does. */
void computeLayoutQuads(const TriangleMesh& surface, const PatchLayoutParameters& parameters, PatchLayout& out);

/** \brief The last stage of computePatchLayout again, at another overlap level: seeds, frames, their
  * move onto the surface and the coverage seeds, on the layout's own quads (the coarse shape and
  * the quad mesh — most of the cost — are kept). Throws Error for an overlap outside [0, 16]. */
void reseedPatchLayout(const TriangleMesh& surface, int overlap, PatchLayout& layout);

}  // namespace patchdict
}  // namespace pcl
