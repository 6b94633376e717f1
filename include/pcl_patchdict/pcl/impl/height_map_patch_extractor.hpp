// HeightMapPatchExtractor<PointInT, PointOutT> (see height_map_patch_extractor.h): the typed shell
// around detail::heightMapHistograms — seeds, frames and surface in, histograms out.
#pragma once

#include <pcl_patchdict/core/error.h>
#include <pcl_patchdict/pcl/conversions.h>
#include <pcl_patchdict/pcl/height_map_patch_extractor.h>
#include <pcl_patchdict/pcl/reference_frame.h>

#include <pcl/features/shot_lrf.h>

#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

template <typename PointInT, typename PointOutT>
void HeightMapPatchExtractor<PointInT, PointOutT>::checkInput() const
{
  const std::string what = "HeightMapPatchExtractor: ";
  if (!input_ || input_->empty())
    throw Error(what + "no seeds (setInputCloud with at least one point)");
  if (k_ != 0)
    throw Error(what + "a patch is the surface within a radius: use setRadiusSearch(r), not setKSearch");
  if (!(search_radius_ > 0.0) || !std::isfinite(search_radius_))
    throw Error(what + "the radius (setRadiusSearch) must be positive and finite");
  if (grid_size_ < 2 || grid_size_ > 256)
    throw Error(what + "the grid size must be in [2, 256], not " + std::to_string(grid_size_));
  if (grid_size_ * grid_size_ != kDescriptorSize)
    throw Error(what + "a " + std::to_string(grid_size_) + "×" + std::to_string(grid_size_) + " grid has " +
                std::to_string(grid_size_ * grid_size_) + " bins, but the descriptor holds " +
                std::to_string(kDescriptorSize) + " (pcl::Histogram<N·N> for an N×N grid)");
}

template <typename PointInT, typename PointOutT>
bool HeightMapPatchExtractor<PointInT, PointOutT>::initCompute()
{
  if (fake_surface_) {  // left by a compute() that threw: the surface was the input of that call
    surface_.reset();
    fake_surface_ = false;
  }
  checkInput();
  // pcl::Feature::initCompute would also build a search tree over the surface, which the heights
  // do not use: the indices and the surface are set up here as it does, and nothing else.
  if (!pcl::PCLBase<PointInT>::initCompute())
    throw Error("HeightMapPatchExtractor: the input cloud or its indices are not usable");
  for (const auto index : *indices_)
    if (index < 0 || static_cast<std::size_t>(index) >= input_->size())
      throw Error("HeightMapPatchExtractor: index " + std::to_string(index) + " is outside the input cloud of " +
                  std::to_string(input_->size()) + " points");
  if (!frames_never_defined_ && frames_ && frames_->size() != indices_->size())
    throw Error("HeightMapPatchExtractor: " + std::to_string(frames_->size()) + " reference frames for " +
                std::to_string(indices_->size()) + " seeds");
  if (!surface_) {
    fake_surface_ = true;
    surface_ = input_;
  }
  search_parameter_ = search_radius_;
  // No frames given: SHOT's, as pcl::SHOTEstimation does.
  typename pcl::SHOTLocalReferenceFrameEstimation<PointInT, pcl::ReferenceFrame>::Ptr lrf(
      new pcl::SHOTLocalReferenceFrameEstimation<PointInT, pcl::ReferenceFrame>());
  lrf->setRadiusSearch(lrf_radius_ > 0.f ? lrf_radius_ : search_radius_);
  lrf->setInputCloud(input_);
  lrf->setIndices(indices_);
  if (!fake_surface_)
    lrf->setSearchSurface(surface_);
  if (!this->initLocalReferenceFrames(indices_->size(), lrf)) {
    this->deinitCompute();
    throw Error("HeightMapPatchExtractor: no reference frames could be set up");
  }
  return true;
}

template <typename PointInT, typename PointOutT>
void HeightMapPatchExtractor<PointInT, PointOutT>::computeFeature(PointCloudOut& output)
{
  std::vector<Eigen::Vector3d> seeds(indices_->size());
  std::vector<Eigen::Matrix3d> frames(indices_->size());
  for (std::size_t i = 0; i < indices_->size(); ++i) {
    const PointInT& p = (*input_)[static_cast<std::size_t>((*indices_)[i])];
    seeds[i] = Eigen::Vector3d(p.x, p.y, p.z);
    frames[i] = fromReferenceFrame((*frames_)[i]);
  }
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> points;
  if (mesh_) {
    fromPolygonMesh(*mesh_, mesh);
  } else {
    points.reserve(surface_->size());
    for (const PointInT& p : *surface_)
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
        points.emplace_back(p.x, p.y, p.z);
  }
  HeightMapParameters parameters;
  parameters.radius = search_radius_;
  parameters.grid_size = grid_size_;
  parameters.num_threads = threads_;
  std::vector<float> values;
  const bool dense = detail::heightMapHistograms(mesh_ ? &mesh : nullptr, points, seeds, frames, parameters, values);
  for (std::size_t i = 0; i < indices_->size(); ++i)
    std::copy(values.begin() + static_cast<std::ptrdiff_t>(i * kDescriptorSize),
              values.begin() + static_cast<std::ptrdiff_t>((i + 1) * kDescriptorSize), output[i].histogram);
  output.is_dense = dense;
}

}  // namespace patchdict
}  // namespace pcl
