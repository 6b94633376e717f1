// HeightMapPatchExtractor — the N×N height-map patches of a surface at given seeds and frames
// (section 3.2 of Sarkar et al. 2017): exact heights from a mesh, or binned heights from a cloud.
#pragma once

#include <pcl_patchdict/core/local_frame.h>
#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/patches/patch_set.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Height-map patch extraction, shaped like a pcl::Feature with local reference frames.
  *
  * Geometry (the paper's section 3.2): a patch of seed s with frame F_s (rows of R_s = the frame's
  * X, Y, Z axes) is a square grid of side √2·r in the XY plane of F_s, centred on s. Bin (i, j) —
  * i the column along X, j the row along Y, both in [0, N) — is row j·N + i of the patch column;
  * its centre is at x = (i + 0.5)/N·side − side/2, y = (j + 0.5)/N·side − side/2 in the frame,
  * and its value is the height Z of the surface there, in the frame (local = R_s·(p − s)).
  * Only surface within the ball of radius r around s (the paper's r-neighbourhood) counts.
  *
  * Two modes:
  *  - setInputMesh: exact heights — every bin centre gets the height of the triangles whose XY
  *    projection (in the frame) contains it, barycentric-interpolated. Noise-free and complete:
  *    binning random samples fills only a fraction of the bins.
  *  - setInputCloud: binning, as in the paper — points within r, in the frame, binned on the
  *    grid; the bin's value is the mean Z of its points.
  * Bins nothing covers are unobserved (mask false, height 0).
  *
  * Frames are the core's (rows X, Y, Z in double, core/local_frame.h; fromReferenceFrames converts
  * PCL's). They must be orthonormal to single precision — the layout's frames are rounded to float
  * (roundToSinglePrecision) — and are used as given, not re-orthonormalised, so the stored rotation
  * is exactly the one the heights were measured in. */
class HeightMapPatchExtractor {
public:
  using Ptr = std::shared_ptr<HeightMapPatchExtractor>;
  using ConstPtr = std::shared_ptr<const HeightMapPatchExtractor>;

  HeightMapPatchExtractor() = default;

  /** Seeds and their frames (one per seed, rows X, Y, Z). */
  void setSeeds(const std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& frames);
  /** Exact heights from the mesh's triangles (clears a cloud set before). Shared: kept alive until replaced. */
  void setInputMesh(const std::shared_ptr<const TriangleMesh>& mesh);
  /** Binned heights from the vertices (faces ignored; clears a mesh set before). */
  void setInputCloud(const std::shared_ptr<const TriangleMesh>& cloud_as_vertices);
  /** r: neighbourhood radius; patch side √2·r. */
  void setRadius(double radius) { radius_ = radius; }
  double getRadius() const { return radius_; }
  /** N: bins per side (default 16). */
  void setGridSize(int grid_size) { grid_size_ = grid_size; }
  int getGridSize() const { return grid_size_; }
  /** Binned mode: 0 (default, the paper's) — a bin's height is the mean of the points in it; > 0 —
    * the biweight-weighted mean, (1 − d²/R²)² with R = reach bins, of the points within R of its centre
    * in the plane, so that random samples sparser than the grid still observe every bin. */
  void setBinReach(double reach) { bin_reach_ = reach; }
  double getBinReach() const { return bin_reach_; }
  /** Threads for the loop over seeds; 0 = OpenMP's default. Results do not depend on it. */
  void setNumberOfThreads(int threads) { threads_ = threads; }
  /** Value stored in PatchSet::source for every patch (which input shape this is). */
  void setSourceIndex(std::int32_t source_index) { source_index_ = source_index; }

  /** Fills `out` with one patch per seed, in seed order. Throws Error for missing or inconsistent
    * input (no surface, frames ≠ seeds, radius ≤ 0, grid outside [2, 256], non-finite or
    * non-orthonormal frames, a mesh without faces or with bad indices). */
  void compute(PatchSet& out) const;

private:
  enum class Mode { None, Mesh, Cloud };
  void checkInput() const;
  void computeMesh(PatchSet& out) const;
  void computeCloud(PatchSet& out) const;

  Mode mode_ = Mode::None;
  std::shared_ptr<const TriangleMesh> surface_;  ///< faces ignored in Mode::Cloud
  std::vector<Eigen::Vector3d> seeds_;
  std::vector<Eigen::Matrix3d> rotations_;
  double radius_ = 0.0;
  int grid_size_ = 16;
  int threads_ = 0;
  double bin_reach_ = 0.0;
  std::int32_t source_index_ = 0;
};

/** A right-handed frame (rows X, Y, Z) whose Z is the given unit normal and whose X is an arbitrary
  * (but deterministic) tangent, rounded as the quads' frames (roundToSinglePrecision): for callers
  * without quad frames, e.g. seeds at random surface points. */
Eigen::Matrix3d frameFromNormal(const Eigen::Vector3d& normal);

}  // namespace patchdict
}  // namespace pcl
