// SparsePatchInpainter<PointInT, PointOutT> (see sparse_patch_inpainter.h): the base's process(),
// then the patch stage over its new points.
#pragma once

#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>

#include <cmath>
#include <vector>

namespace pcl {
namespace patchdict {

template <typename PointInT, typename PointOutT>
void SparsePatchInpainter<PointInT, PointOutT>::performProcessing(PointCloudOut& output)
{
  patch_report_ = CloudPatchFillReport();
  patch_report_.decision = "not run";
  base_.setInputCloud(input_);
  base_.setIndices(indices_);
  base_.process(output);
  const CloudDenoisingReport& report = base_.getReport();
  if (base_.getMode() == Mode::Denoise) {
    patch_report_.reason = "denoising: the geometric base (patch denoising of clouds is not implemented yet)";
    return;
  }
  if (report.depth_image || output.height > 1) {
    patch_report_.reason = "an organised depth image, filled in place in the sensor's image";
    return;
  }
  const std::size_t added = report.points_added;
  if (added == 0 || added > output.size()) {
    patch_report_.reason = "no point was added";
    return;
  }
  const std::size_t first_added = output.size() - added;
  std::vector<Eigen::Vector3d> observed, fill, corrected;
  observed.reserve(first_added);
  for (std::size_t i = 0; i < first_added; ++i) {
    const Eigen::Vector3d p = output[i].getVector3fMap().template cast<double>();
    if (p.allFinite())
      observed.push_back(p);
  }
  fill.reserve(added);
  for (std::size_t i = first_added; i < output.size(); ++i)
    fill.push_back(output[i].getVector3fMap().template cast<double>());
  correctCloudFillWithPatches(observed, fill, report.mean_spacing, patch_options_, corrected, &patch_report_);
  if (patch_report_.decision != "applied")
    return;
  for (std::size_t i = 0; i < added; ++i)
    output[first_added + i].getVector3fMap() = corrected[i].template cast<float>();
}

}  // namespace patchdict
}  // namespace pcl
