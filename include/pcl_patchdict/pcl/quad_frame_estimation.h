// QuadFrameEstimation — where the patches of a point cloud or a pcl::PolygonMesh go: seeds on the
// surface, each with a local reference frame from the field-aligned quads of its coarse shape
// (sections 3.1 and 3.3 of Sarkar et al. 2017). A PCL keypoint detector and local-reference-frame
// estimator in one (the shapes of pcl::Keypoint and pcl::SHOTLocalReferenceFrameEstimation).
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/quads/patch_layout.h>

#include <pcl/PolygonMesh.h>
#include <pcl/pcl_base.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace pcl {
namespace patchdict {

/** What the last QuadFrameEstimation::compute did; lengths in the input's units. */
struct QuadFrameReport {
  bool from_cloud = false;          ///< the input was a cloud (else a pcl::PolygonMesh)
  std::size_t input_points = 0;     ///< finite points used (cloud), or the mesh's vertices
  bool normals_given = false;       ///< the cloud's own normals were used (else estimated, Hoppe et al.)
  int poisson_depth = 0;            ///< cloud: the depth of its Poisson surface
  std::size_t surface_faces = 0;    ///< faces of the surface the seeds lie on (cloud: its Poisson surface)
  double quad_length = 0.0;         ///< L used
  std::size_t coarse_faces = 0;     ///< faces of the smoothed shape the quads are laid on
  std::size_t quad_faces = 0, quads = 0;  ///< faces of the quad mesh, and how many of them are quads
  int singularities = 0;            ///< of the orientation field
  std::size_t seeds = 0;
  std::size_t coverage_seeds = 0;   ///< seeds added where no quad's patch reaches (seed face −1)
  double mean_seed_shift = 0.0;     ///< mean distance the seeds moved from the quads onto the surface
  double seconds_surface = 0.0, seconds_coarse = 0.0, seconds_quads = 0.0, seconds_frames = 0.0;
};

namespace detail {
/** The type-free core of QuadFrameEstimation. `surface` in the input's units: a mesh, or without
  * faces a cloud (with normals when it has one per point). `parameters.quad_length` is in the
  * input's units too, 0 = automatic (0.03 × the largest bounding-box side). Works in the unit
  * cube, as the tool does (UnitCubeNormalization): a cloud gets its coarse Poisson surface
  * (CoarseMeshEstimation), then computePatchLayout runs on the surface; `layout` comes back in the
  * input's units (seeds, coarse shape, quads, quad_length; frames unchanged). */
void estimateQuadFrames(const TriangleMesh& surface, const PatchLayoutParameters& parameters, PatchLayout& layout,
                        QuadFrameReport& report);
/** A quad-dominant mesh as a pcl::PolygonMesh (x y z float32; polygons of 3, 4 or more vertices). */
void quadMeshToPolygonMesh(const QuadMesh& quads, pcl::PolygonMesh& out);
}  // namespace detail

/** \brief Seeds and local reference frames where the paper puts its patches, from a point cloud
  * (setInputCloud, with setIndices honoured) or a surface mesh (setInputPolygonMesh, which takes
  * precedence while set):
  *
  *  1. the input is scaled into the unit cube (largest bounding-box side 1), as the tool does;
  *  2. a cloud becomes its coarse surface: normals (the cloud's own when PointInT has them and
  *     every used point's is finite and non-zero, else estimated and oriented by Hoppe et al.'s
  *     propagation), pcl::Poisson at a depth from the spacing, trimmed where it leaves the samples,
  *     Taubin-smoothed (CoarseMeshEstimation, the tool's `patches` path); a mesh is its own surface;
  *  3. computePatchLayout on that surface: a coarse shape (setSmoothingIterations Laplacian
  *     iterations), field-aligned quads of side L (QuadRemesher, after Instant Meshes), one frame
  *     per quad (computeQuadFrames: Z the quad normal, X along its sides, consistent across
  *     quads), 1 + 4k seeds per quad for overlap k, moved onto the surface along their frames;
  *     surface points no patch reaches get seeds of their own;
  *  4. seeds and quads come back in the input's coordinates.
  *
  * compute(seeds, frames) gives one pcl::PointNormal per seed (position; normal = the frame's Z,
  * pointing out of the surface; curvature 0) and its pcl::ReferenceFrame — what
  * HeightMapPatchExtractor takes as its input cloud (a PointNormal cloud, or copy the xyz into
  * PointInT) and its reference frames. Same input and parameters: the same seeds and frames,
  * whatever the thread count. Throws pcl::patchdict::Error (one line) for a missing or too small
  * input, parameters out of range, or an L too large for the shape (fewer than 6 quads).
  *
  * Compiled for pcl::PointXYZ, pcl::PointNormal and pcl::PointXYZRGBNormal; for other types,
  * define PCL_NO_PRECOMPILE before including this header. */
template <typename PointInT>
class QuadFrameEstimation : public pcl::PCLBase<PointInT> {
public:
  using Ptr = std::shared_ptr<QuadFrameEstimation<PointInT>>;
  using ConstPtr = std::shared_ptr<const QuadFrameEstimation<PointInT>>;
  using PointCloudIn = pcl::PointCloud<PointInT>;
  using PointCloudSeeds = pcl::PointCloud<pcl::PointNormal>;
  using PointCloudLRF = pcl::PointCloud<pcl::ReferenceFrame>;

  QuadFrameEstimation() { parameters_.quad_length = 0.0; }

  /** A surface mesh instead of the cloud (shared: kept alive until replaced; nullptr: back to the
    * cloud). Polygons of more than three vertices are fan-triangulated. */
  void setInputPolygonMesh(const pcl::PolygonMesh::ConstPtr& mesh) { mesh_ = mesh; }
  pcl::PolygonMesh::ConstPtr getInputPolygonMesh() const { return mesh_; }

  /** L, the side of a quad and of a patch, in the input's units; 0 (default) = 0.03 × the input's
    * largest bounding-box side, the tool's default. */
  void setQuadLength(double quad_length) { parameters_.quad_length = quad_length; }
  double getQuadLength() const { return parameters_.quad_length; }
  /** Overlap level k ≥ 0 (default 1): 1 + 4k seeds per quad. */
  void setOverlap(int overlap) { parameters_.overlap = overlap; }
  int getOverlap() const { return parameters_.overlap; }
  /** Laplacian smoothing iterations of the coarse shape the quads are laid on (default 30). */
  void setSmoothingIterations(int iterations) { parameters_.smoothing_iterations = iterations; }
  int getSmoothingIterations() const { return parameters_.smoothing_iterations; }
  /** Seed of the quad remesher's random choices (default 0). */
  void setSeed(std::uint64_t seed) { parameters_.seed = seed; }
  std::uint64_t getSeed() const { return parameters_.seed; }
  /** Threads; 0 = OpenMP's default. Results do not depend on it. */
  void setNumberOfThreads(int threads) { parameters_.num_threads = threads; }

  /** \brief Seeds (with the frame's Z as normal) and one reference frame per seed. */
  void compute(PointCloudSeeds& seeds, PointCloudLRF& frames);

  /** The smoothed coarse shape the quads of the last compute() were laid on. */
  void getCoarseMesh(pcl::PolygonMesh& mesh) const;
  /** The quad-dominant mesh of the last compute() (polygons of 4 vertices, a few of 3 or more). */
  void getQuadMesh(pcl::PolygonMesh& mesh) const { detail::quadMeshToPolygonMesh(layout_.quads, mesh); }
  /** The quad of each seed of the last compute() (an index into getQuadMesh's polygons), −1 for a
    * seed added where no quad's patch reaches. */
  const std::vector<std::int32_t>& getSeedQuads() const { return layout_.seed_faces; }
  const QuadFrameReport& getReport() const { return report_; }

protected:
  using pcl::PCLBase<PointInT>::input_;
  using pcl::PCLBase<PointInT>::indices_;

private:
  /** The finite points at the indices (and their normals, when PointInT has them and all are usable). */
  void readCloud(TriangleMesh& surface);

  pcl::PolygonMesh::ConstPtr mesh_;
  PatchLayoutParameters parameters_;  ///< quad_length in the input's units, 0 = automatic
  PatchLayout layout_;                ///< of the last compute(), in the input's units
  QuadFrameReport report_;
};

}  // namespace patchdict
}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl_patchdict/pcl/impl/quad_frame_estimation.hpp>
#endif
