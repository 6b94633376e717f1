// Height maps — the N×N height-map patches of a surface at given seeds and frames (section 3.2 of
// Sarkar et al. 2017): exact heights from a mesh, or binned heights from a cloud. Free functions
// over the core's types; the pcl::Feature that computes them from PCL clouds is
// pcl/height_map_patch_extractor.h.
#pragma once

#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/patches/patch_set.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {

/** What the height maps are measured with. */
struct HeightMapParameters {
  double radius = 0.0;            ///< r, the neighbourhood radius (required, > 0); patch side √2·r
  int grid_size = 16;             ///< N, bins per side, in [2, 256]
  int num_threads = 0;            ///< threads of the loop over seeds; 0 = OpenMP's default. Results do not depend on it
  std::int32_t source_index = 0;  ///< stored in PatchSet::source for every patch (which input shape this is)
  /// extractCloudHeightMaps: 0 (default, the paper's) — a bin's height is the mean of the points in
  /// it; > 0 — the biweight-weighted mean, (1 − d²/R²)² with R = bin_reach bins, of the points within
  /// R of its centre in the plane, so that random samples sparser than the grid still observe every bin.
  double bin_reach = 0.0;
};

/* Geometry of both functions (the paper's section 3.2): a patch of seed s with frame F_s (rows of
 * R_s = the frame's X, Y, Z axes) is a square grid of side √2·r in the XY plane of F_s, centred on
 * s. Bin (i, j) — i the column along X, j the row along Y, both in [0, N) — is row j·N + i of the
 * patch column; its centre is at x = (i + 0.5)/N·side − side/2, y = (j + 0.5)/N·side − side/2 in
 * the frame, and its value is the height Z of the surface there, in the frame
 * (local = R_s·(p − s)). Only surface within the ball of radius r around s (the paper's
 * r-neighbourhood) counts. Bins nothing covers are unobserved (mask false, height 0).
 *
 * Frames are the core's (rows X, Y, Z in double, core/local_frame.h; fromReferenceFrames converts
 * PCL's), one per seed. They must be orthonormal to single precision — the layout's frames are
 * rounded to float (roundToSinglePrecision) — and are used as given, not re-orthonormalised, so the
 * stored rotation is exactly the one the heights were measured in.
 *
 * Both fill `out` with one patch per seed, in seed order, and throw Error for inconsistent input:
 * a surface without points or with non-finite coordinates, frames ≠ seeds, radius ≤ 0 or not
 * finite, grid outside [2, 256], non-finite seeds or frames, non-orthonormal or left-handed
 * frames. */

/** \brief Exact heights: every bin centre gets the height of the triangles whose XY projection (in
  * the frame) contains it, barycentric-interpolated. Noise-free and complete: binning random
  * samples fills only a fraction of the bins. Where several sheets lie over one bin centre (a
  * fold), the one closest to the patch plane is kept. Also throws Error for a mesh without faces
  * or with bad indices. */
void extractMeshHeightMaps(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& seeds,
                           const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters,
                           PatchSet& out);

/** \brief Binning, as in the paper: points within r, in the frame, binned on the grid; a bin's
  * value is the mean Z of its points (summed in point order: bit-identical for any thread count),
  * or with bin_reach > 0 the biweight-weighted mean of the points within reach; bins without
  * points are unobserved. */
void extractCloudHeightMaps(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& seeds,
                            const std::vector<Eigen::Matrix3d>& frames, const HeightMapParameters& parameters,
                            PatchSet& out);

/** The check every frame passes: throws Error unless it is finite, orthonormal to single precision
  * and right-handed; `index` is the seed it belongs to, named in the message. */
void checkHeightMapFrame(const Eigen::Matrix3d& frame, std::size_t index);

/** A right-handed frame (rows X, Y, Z) whose Z is the given unit normal and whose X is an arbitrary
  * (but deterministic) tangent, rounded as the quads' frames (roundToSinglePrecision): for callers
  * without quad frames, e.g. seeds at random surface points. */
Eigen::Matrix3d frameFromNormal(const Eigen::Vector3d& normal);

}  // namespace patchdict
}  // namespace pcl
