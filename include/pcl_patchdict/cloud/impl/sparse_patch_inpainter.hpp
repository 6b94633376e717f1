// SparsePatchInpainter<PointInT, PointOutT> (see sparse_patch_inpainter.h): the base's process(),
// then the patch stage over its new points.
#pragma once

#include <pcl_patchdict/cloud/sparse_patch_inpainter.h>

#include <cmath>
#include <vector>

namespace pcl {
namespace patchdict {

namespace detail {
/** The base's estimated mean squared height error at the bandwidth it chose: Stein's unbiased form
  * (mean squared residual − σ² + 2σ²·mean leverage) of its risk sample; 0 when it made none (a
  * given bandwidth, the depth law). */
inline double baseRisk(const CloudRepairReport& report)
{
  const CloudRepairReport::BandwidthRisk* chosen = nullptr;
  for (const auto& candidate : report.bandwidth_risks)
    if (!chosen || std::abs(candidate.factor - report.bandwidth_factor) < std::abs(chosen->factor - report.bandwidth_factor))
      chosen = &candidate;
  if (!chosen || report.depth_law)
    return 0.0;
  const double s2 = report.noise_sigma * report.noise_sigma;
  return std::max(0.0, chosen->mean_squared_residual - s2 + 2.0 * s2 * chosen->mean_leverage);
}
}  // namespace detail

template <typename PointInT, typename PointOutT>
void SparsePatchInpainter<PointInT, PointOutT>::performProcessing(PointCloudOut& output)
{
  patch_report_ = denoise_report_ = CloudPatchReport();
  nonlocal_report_ = NonlocalPatchReport();
  base_.setInputCloud(input_);
  base_.setIndices(indices_);
  base_.process(output);
  const CloudRepairReport& report = base_.getReport();
  if (report.depth_image || report.range_image || output.height > 1) {
    patch_report_.reason = denoise_report_.reason = nonlocal_report_.reason =
        report.range_image ? "a spinning LiDAR's range image, repaired along its beams"
                           : "an organised depth image, repaired in the sensor's image";
    return;
  }
  const std::size_t added = base_.getMode() == Mode::Denoise ? 0 : report.points_added;
  if (added > output.size())
    return;
  const std::size_t first_added = output.size() - added;
  const auto position = [&](std::size_t i) { return Eigen::Vector3d(output[i].getVector3fMap().template cast<double>()); };
  if (base_.getMode() != Mode::Complete) {
    // Denoising: the kept points, binned where they were measured, moved from where the base put them.
    const pcl::Indices& kept = base_.getKeptIndices();
    std::vector<Eigen::Vector3d> noisy, denoised, corrected;
    for (std::size_t i = 0; i < first_added && i < kept.size(); ++i) {
      noisy.push_back((*input_)[static_cast<std::size_t>(kept[i])].getVector3fMap().template cast<double>());
      denoised.push_back(position(i));
    }
    if (noisy.size() >= 100) {
      // The dictionary's patches (K-SVD on the surface) denoise only over a given dictionary: self-similar
      // ones were declined on every cloud measured and were 2–4 × worse when forced (docs/results.md).
      if (patch_options_.dictionary) {
        denoiseCloudWithPatches(noisy, denoised, report.mean_spacing, report.noise_sigma, detail::baseRisk(report),
                                patch_options_, corrected, &denoise_report_);
      } else if (patch_options_.decision.mode == PatchDecision::Never) {
        denoise_report_.outcome = PatchOutcome::Declined;
        denoise_report_.reason = "patches off";
      } else {
        denoise_report_.reason = "no dictionary given: self-similar patches are not tried (declined on every cloud measured)";
      }
      if (denoise_report_.outcome == PatchOutcome::Applied) {
        nonlocal_report_.reason = "the dictionary's patches applied";
      } else {
        // The base's bandwidth, to refit it on half the points (none under a depth law: declined).
        const double h = report.depth_law ? 0.0 : report.bandwidth;
        denoiseCloudNonlocally(noisy, denoised, report.mean_spacing, report.noise_sigma, h, nonlocal_options_,
                               corrected, &nonlocal_report_);
      }
      if (denoise_report_.outcome == PatchOutcome::Applied || nonlocal_report_.outcome == PatchOutcome::Applied)
        for (std::size_t i = 0; i < corrected.size(); ++i)
          output[i].getVector3fMap() = corrected[i].template cast<float>();
    } else {
      denoise_report_.reason = nonlocal_report_.reason = "fewer than 100 points kept";
    }
  }
  if (added == 0) {
    patch_report_.reason = base_.getMode() == Mode::Denoise ? "denoising only" : "no point was added";
    return;
  }
  std::vector<Eigen::Vector3d> observed, fill, corrected;
  observed.reserve(first_added);
  for (std::size_t i = 0; i < first_added; ++i)
    if (position(i).allFinite())
      observed.push_back(position(i));
  fill.reserve(added);
  for (std::size_t i = first_added; i < output.size(); ++i)
    fill.push_back(position(i));
  correctCloudFillWithPatches(observed, fill, report.mean_spacing, patch_options_, corrected, &patch_report_);
  if (patch_report_.outcome != PatchOutcome::Applied)
    return;
  for (std::size_t i = 0; i < added; ++i)
    output[first_added + i].getVector3fMap() = corrected[i].template cast<float>();
}

}  // namespace patchdict
}  // namespace pcl
