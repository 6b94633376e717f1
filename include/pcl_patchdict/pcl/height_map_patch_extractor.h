// HeightMapPatchExtractor — the paper's N×N height-map patches (section 3.2 of Sarkar et al. 2017)
// as a pcl::Feature with local reference frames, in the shape of pcl::SHOTEstimation: one
// pcl::Histogram<N·N> per seed, NaN in the bins no surface covers.
#pragma once

#include <pcl_patchdict/core/triangle_mesh.h>
#include <pcl_patchdict/patches/height_maps.h>

#include <pcl/PolygonMesh.h>
#include <pcl/features/feature.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <cmath>
#include <memory>
#include <type_traits>
#include <vector>

namespace pcl {
namespace patchdict {

namespace detail {
/** The type-free core of HeightMapPatchExtractor: the height maps of the seeds whose position and
  * frame (rows X, Y, Z) are finite — each frame checked (checkHeightMapFrame) under its own seed
  * index — from the mesh's triangles when `mesh` is given (extractMeshHeightMaps), else binned from
  * `points` (extractCloudHeightMaps). `out` gets N² floats per seed, bin j·N + i at j·N + i: the
  * height, or NaN where unobserved and in every bin of a seed without a valid position or frame.
  * Returns whether every value is finite. */
bool heightMapHistograms(const TriangleMesh* mesh, const std::vector<Eigen::Vector3d>& points,
                         const std::vector<Eigen::Vector3d>& seeds, const std::vector<Eigen::Matrix3d>& frames,
                         const HeightMapParameters& parameters, std::vector<float>& out);
}  // namespace detail

/** \brief Height-map patches as a PCL feature: for every point of the input cloud (the seeds, with
  * setIndices honoured) and its local reference frame, the surface around it seen from the frame
  * as an N×N grid of heights, one `pcl::Histogram<N·N>` per seed.
  *
  * The shape of pcl::SHOTEstimation: setInputCloud(seeds), setSearchSurface(cloud) (default: the
  * seeds themselves), setInputReferenceFrames(frames), setRadiusSearch(r), compute(output), and
  * usable through a pcl::Feature<PointInT, PointOutT>::Ptr.
  *
  * Geometry (the paper's): the patch of a seed s with frame F is a square of side √2·r in F's XY
  * plane, centred on s; bin (i, j) — i along X, j along Y — is histogram entry j·N + i, its centre
  * at ((i + ½)/N − ½, (j + ½)/N − ½)·√2·r in the frame, its value the height along Z of the surface
  * there (local = R·(p − s), R's rows F's X, Y, Z). Only surface within r of s counts. Heights are:
  *  - binned from the search surface's points (the default): a bin's value is the mean height of
  *    the points in it (extractCloudHeightMaps);
  *  - exact, with setInputPolygonMesh: the height of the mesh's triangles at the bin centre
  *    (extractMeshHeightMaps); the search surface is then not used.
  * A bin no surface covers is NaN, as PCL marks values it could not compute; a seed without a valid
  * frame (NaN, as SHOTLocalReferenceFrameEstimation gives where it has too few neighbours) or with
  * a non-finite position gets an all-NaN histogram. The output's is_dense is false when any bin is
  * NaN. patch_histograms.h codes such histograms with a PatchDictionary, NaN bins as unobserved.
  *
  * Frames: the ones given (setInputReferenceFrames, one per seed — QuadFrameEstimation's, where the
  * paper's patches go, X consistent across the surface); without them, as pcl::SHOTEstimation
  * does, pcl::SHOTLocalReferenceFrameEstimation's at radius getLRFRadius() (0: the search radius)
  * — Z the normal, X the dominant direction of the neighbourhood, not consistent between seeds. A
  * given frame must be orthonormal to single precision and right-handed.
  *
  * Grid: N·N must be the descriptor's size — pcl::Histogram<256> holds 16 × 16 bins (the default
  * N is √M). Failures throw pcl::patchdict::Error with one line (where pcl::Feature would print
  * and return an empty output): no seeds, k-search instead of a radius, a radius ≤ 0, N·N ≠ M or
  * N outside [2, 256], frames ≠ seeds, a frame not orthonormal or left-handed, a surface without
  * finite points, a bad mesh. Same input and parameters: the same output, whatever the threads.
  *
  * Compiled for pcl::PointXYZ, pcl::PointNormal and pcl::PointXYZRGBNormal with
  * pcl::Histogram<256>; for other types define PCL_NO_PRECOMPILE before including this header. */
template <typename PointInT, typename PointOutT = pcl::Histogram<256>>
class HeightMapPatchExtractor : public pcl::Feature<PointInT, PointOutT>,
                                public pcl::FeatureWithLocalReferenceFrames<PointInT, pcl::ReferenceFrame> {
public:
  using Ptr = std::shared_ptr<HeightMapPatchExtractor<PointInT, PointOutT>>;
  using ConstPtr = std::shared_ptr<const HeightMapPatchExtractor<PointInT, PointOutT>>;
  using PointCloudIn = typename pcl::Feature<PointInT, PointOutT>::PointCloudIn;
  using PointCloudOut = typename pcl::Feature<PointInT, PointOutT>::PointCloudOut;
  using pcl::Feature<PointInT, PointOutT>::feature_name_;
  using pcl::Feature<PointInT, PointOutT>::getClassName;

  /** M, the bins a PointOutT holds. */
  static constexpr int kDescriptorSize = pcl::detail::traits::descriptorSize_v<PointOutT>;
  static_assert(std::is_same<PointOutT, pcl::Histogram<kDescriptorSize>>::value,
                "HeightMapPatchExtractor writes pcl::Histogram<N·N> descriptors");

  HeightMapPatchExtractor() { feature_name_ = "HeightMapPatchExtractor"; }

  /** N, bins per side (default √M, when M is a square). N·N must equal M. */
  void setGridSize(int grid_size) { grid_size_ = grid_size; }
  int getGridSize() const { return grid_size_; }
  /** Exact heights from this mesh instead of binned points of the search surface (shared: kept
    * alive until replaced; nullptr: back to binning). */
  void setInputPolygonMesh(const pcl::PolygonMesh::ConstPtr& mesh) { mesh_ = mesh; }
  pcl::PolygonMesh::ConstPtr getInputPolygonMesh() const { return mesh_; }
  /** Radius of the default SHOT frames, used when no frames are given (0: the search radius). */
  void setLRFRadius(float radius) { lrf_radius_ = radius; }
  float getLRFRadius() const { return lrf_radius_; }
  /** Threads of the loop over seeds; 0 = OpenMP's default. The output does not depend on it. */
  void setNumberOfThreads(int threads) { threads_ = threads; }

protected:
  /** Checks the input and parameters (Error otherwise), sets up the search surface and the frames
    * (given, or SHOT's). No search tree is built: the heights use their own (heightMapHistograms). */
  bool initCompute() override;
  void computeFeature(PointCloudOut& output) override;

private:
  using pcl::Feature<PointInT, PointOutT>::input_;
  using pcl::Feature<PointInT, PointOutT>::indices_;
  using pcl::Feature<PointInT, PointOutT>::surface_;
  using pcl::Feature<PointInT, PointOutT>::fake_surface_;
  using pcl::Feature<PointInT, PointOutT>::search_radius_;
  using pcl::Feature<PointInT, PointOutT>::search_parameter_;
  using pcl::Feature<PointInT, PointOutT>::k_;
  using pcl::FeatureWithLocalReferenceFrames<PointInT, pcl::ReferenceFrame>::frames_;
  using pcl::FeatureWithLocalReferenceFrames<PointInT, pcl::ReferenceFrame>::frames_never_defined_;

  static constexpr int defaultGridSize()
  {
    int n = 1;
    while ((n + 1) * (n + 1) <= kDescriptorSize)
      ++n;
    return n;
  }
  void checkInput() const;

  int grid_size_ = defaultGridSize();
  pcl::PolygonMesh::ConstPtr mesh_;
  float lrf_radius_ = 0.f;
  int threads_ = 0;
};

}  // namespace patchdict
}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl_patchdict/pcl/impl/height_map_patch_extractor.hpp>
#endif
