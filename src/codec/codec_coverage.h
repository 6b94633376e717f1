// Coverage patches of the .pdc codec: patches with stored frames for the parts of a surface the
// quad mesh misses (thin parts narrower than L: ears, fingers, a torch), and their decoded pieces.
// Private to the library (PatchCodec uses it).
#pragma once

#include <pcl_patchdict/geometry/metrics.h>
#include <pcl_patchdict/core/triangle_mesh.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace pcl {
namespace patchdict {
namespace detail {

/** A coverage patch's stored frame: its seed on the position grid, its Z as an octahedral unit
  * vector (Cigolle et al. 2014, "A survey of efficient representations for independent unit
  * vectors", JCGT 3(2)) and its X as an angle in the tangent plane. */
struct CoverageFrame {
  std::array<std::uint32_t, 3> position{{0, 0, 0}};  ///< position_bits each, like the quad vertices
  std::uint32_t normal_u = 0, normal_v = 0;           ///< kCoverageNormalBits each
  std::uint32_t angle = 0;                            ///< kCoverageAngleBits: [0, π) (X and −X alike)
};
constexpr std::uint32_t kCoverageNormalBits = 12, kCoverageAngleBits = 8;

/** The seed and rotation (rows X, Y, Z) a stored frame stands for; encoder and decoder alike. */
void coverageSeedAndRotation(const CoverageFrame& frame, std::uint32_t position_bits, Eigen::Vector3d& seed,
                             Eigen::Matrix3d& rotation);

/** Encoder: frames of coverage patches for the input's parts that the decoded surface misses.
  *
  * Every input vertex farther than `tolerance` from `decoded` is uncovered. Greedily, farthest
  * first (ties by index): a patch is seeded at the vertex, Z = the mean normal of the vertices
  * within r/4 that face its way, X = the main axis of its r-neighbourhood in the tangent plane
  * (a thin part runs along X, as quads follow principal directions); the uncovered vertices the
  * patch sees — inside 80 % of its square, within r of the seed, their normals facing Z — are then
  * covered (with the seed itself, even when the patch is dropped for seeing fewer than two of
  * them). Stops when every vertex is covered or after `max_patches` frames; the caller may drop
  * frames whose patch then keeps no complete cell, which still count here. Deterministic. */
std::vector<CoverageFrame> chooseCoverageFrames(const TriangleMesh& surface, const PointToMeshDistance& decoded,
                                                double radius, double tolerance, std::uint32_t position_bits,
                                                std::size_t max_patches);

/** Bins a coverage patch must code: observed bins whose surface point lies farther than
  * `tolerance` from the decoded surface (`bin_distances`), grown by one bin within the observed
  * ones so that neighbouring pieces and the decoded surface meet. Row j·N + i, like PatchSet. */
std::vector<char> coverageBins(const std::vector<char>& observed, const std::vector<double>& bin_distances,
                               double tolerance, int grid);

/** The surface points of a patch's bins, seed + Rᵀ(x, y, h), in bin order (row j·N + i). */
std::vector<Eigen::Vector3d> binPoints(const Eigen::Vector3d& seed, const Eigen::Matrix3d& rotation, double side,
                                       int grid, const Eigen::VectorXd& heights);

/** Cells (2×2 bins) whose four bins are all kept: what a piece will have of surface. */
std::size_t completeCells(const std::vector<char>& kept, int grid);

/** Decoder: appends a decoded coverage patch to `out` as a grid of its kept bins' points, two
  * triangles per cell whose four corners are kept (bins no such cell uses add no vertex). */
void appendCoveragePiece(const Eigen::Vector3d& seed, const Eigen::Matrix3d& rotation, double side, int grid,
                         const Eigen::VectorXd& heights, const std::vector<char>& kept, TriangleMesh& out);

}  // namespace detail
}  // namespace patchdict
}  // namespace pcl
