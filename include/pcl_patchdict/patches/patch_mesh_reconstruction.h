// PatchMeshReconstruction — patches back to a surface (section 3.4 of Sarkar et al. 2017): every
// vertex of a target mesh is re-estimated from the patches whose grid it falls in, then averaged.
#pragma once

#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/core/local_frame.h>  // patchContains
#include <pcl_patchdict/core/triangle_mesh.h>

#include <memory>

namespace pcl {
namespace patchdict {

/** One vertex seen by one patch: its tangent coordinates in the patch frame. */
struct VertexPatchSample {
  std::int32_t vertex = -1;
  std::int32_t patch = -1;
  double x = 0.0, y = 0.0;  ///< in the patch frame
  double z = 0.0;           ///< the vertex's own height in the frame
};

/** \brief Rebuilds vertex positions from a PatchSet on the connectivity of a target mesh.
  *
  * Mapping (the paper's vertex ↔ (patch, bin) map): vertex v belongs to patch p when it lies in
  * the patch's square (|x|, |y| < side/2 in the frame) and within its r-ball, as the surface the
  * patch was sampled from does, and its vertex normal does not face away from the frame's Z (a
  * vertex on the inside of a thin wall belongs to the patches of that side).
  *
  * Rules:
  *  - BinCentres (the paper): v's estimate from p is the global position of the centre of the bin
  *    it falls in, at that bin's height; positions are quantised to bin centres.
  *  - Bilinear (ours, the default): v keeps its own (x, y) in the frame and takes the patch height
  *    bilinearly interpolated there (linearly extrapolated over the outer half-bins); only the
  *    height is taken from the patch, so vertices do not slide along the surface. On identity
  *    round trips (test ReliefAndBunnyIdentityRoundTrips) its vertex RMSE is lower than
  *    BinCentres' and its surface PSNR slightly lower (a bin-centre point lies exactly on the
  *    sampled surface, only displaced along it); figures in docs/. Vertex positions are what inpainting is judged
  *    by, and tangential drift is what we measured losing to the bi-Laplacian.
  * Estimates whose bins are unobserved, or whose height is more than half a patch side from the
  * vertex's own (another sheet of a folded surface), are skipped. Of three or more estimates,
  * those farther than 3 × their median distance from the coordinate-wise median (and more than
  * a bin) are dropped as well. A vertex keeps the mean of its remaining estimates; a vertex no
  * patch covers takes the mean of its reconstructed 1-ring. */
class PatchMeshReconstruction {
public:
  using Ptr = std::shared_ptr<PatchMeshReconstruction>;
  using ConstPtr = std::shared_ptr<const PatchMeshReconstruction>;

  enum class Rule { BinCentres, Bilinear };

  struct Report {
    std::size_t vertices_covered = 0;   ///< vertices with at least one patch estimate
    std::size_t vertices_from_ring = 0; ///< filled from their 1-ring
    std::size_t vertices_unchanged = 0; ///< no estimate and no reconstructed neighbour
    double mean_estimates = 0.0;        ///< estimates per covered vertex (after rejection)
    std::size_t estimates_rejected = 0; ///< estimates dropped as far from their vertex's median
    std::vector<std::int32_t> estimates;  ///< per vertex: how many patches estimated it
    /** Per vertex: no estimate, and at least one patch's square held it over unobserved bins —
      * the patches saw no surface there (a decoder trims such vertices; see PatchCodec). */
    std::vector<char> off_surface;
  };

  /** The patches, shared (kept alive until they are replaced). */
  void setPatches(const std::shared_ptr<const PatchSet>& patches) { patches_ = patches; }
  /** The target mesh M_r: its vertices are re-estimated, its faces give the 1-rings. */
  void setTargetMesh(const std::shared_ptr<const TriangleMesh>& mesh) { target_ = mesh; }
  void setRule(Rule rule) { rule_ = rule; }
  Rule getRule() const { return rule_; }

  /** Every (vertex, patch) pair of the mapping, in vertex order. */
  std::vector<VertexPatchSample> computeMapping() const;
  /** The reconstructed mesh: the target's faces with re-estimated vertices. Throws Error if the
    * patches or the target are missing or inconsistent. */
  void compute(TriangleMesh& out, Report* report = nullptr) const;

private:
  void checkInput() const;

  std::shared_ptr<const PatchSet> patches_;
  std::shared_ptr<const TriangleMesh> target_;
  Rule rule_ = Rule::Bilinear;
};

/** \brief The point-cloud form of a patch set (for cloud inputs, which have no vertices to move):
  * every observed bin of every patch as a 3D point — the bin centre at its height, in world
  * coordinates (seed + Rᵀ·(x, y, h)); in patch order, bins row by row. */
std::vector<Eigen::Vector3d> patchSetToPoints(const PatchSet& patches);

}  // namespace patchdict
}  // namespace pcl
