// SparsePatchInpainter — the paper's pipeline on point clouds (pcl::CloudSurfaceProcessing): the
// geometric repair as the base, patches of a dictionary where they are measured to do better.
#pragma once

#include <pcl_patchdict/cloud/cloud_patch_correction.h>
#include <pcl_patchdict/cloud/geometric_cloud_repair.h>
#include <pcl_patchdict/cloud/nonlocal_patch_denoising.h>

#include <pcl/point_cloud.h>
#include <pcl/surface/processing.h>

#include <memory>

namespace pcl {
namespace patchdict {

/** \brief Repairs a point cloud as Sarkar et al. (2017) repair a mesh: geometry is the base, the
  * patches its correction, applied only where they are measured to help.
  *
  *  1. The base is a GeometricCloudRepair (local quadrics, spline and implicit fills, depth
  *     images; getGeometricRepair() sets it up): it denoises, and in the Complete modes adds
  *     points in the holes at the input's density.
  *  2. Unorganised clouds, Denoise modes: over a given dictionary (setDictionary),
  *     denoiseCloudWithPatches moves the base's points onto patches binned from the points as
  *     measured and sparse-coded to the noise level, when cross-validation measures them ahead
  *     (getDenoisingPatchReport()). Otherwise, or when it declines, denoiseCloudNonlocally averages
  *     similar patches across the cloud where a coupled bootstrap check measures the average ahead
  *     of the base (getNonlocalPatchReport(): the decision, both estimates, the seconds); clouds of
  *     more than NonlocalPatchOptions::max_checked_points are left to the base unless forced.
  *  3. Unorganised clouds, Complete modes: correctCloudFillWithPatches moves the new points onto
  *     patches completed by masked OMP over a dictionary (setDictionary; none: self-similar, learned
  *     from the cloud's own patches), when the relief check measures the dictionary ahead of a
  *     smooth fill (setPatchDecision(Auto), the default); otherwise the base is the result, point for
  *     point. getPatchReport() says what was decided, and why.
  *
  * Output, fields, organisation, getKeptIndices() and getAddedSources() are the base's (the
  * patches move the new points, never add or drop one). Organised depth images are filled in place
  * by the base, in the sensor's image; the patch stage does not run on them (its report says so).
  * Deterministic for a given input and parameters, whatever the thread count; throws
  * pcl::patchdict::Error for bad input or parameters. */
template <typename PointInT, typename PointOutT = PointInT>
class SparsePatchInpainter : public pcl::CloudSurfaceProcessing<PointInT, PointOutT> {
public:
  using Ptr = std::shared_ptr<SparsePatchInpainter<PointInT, PointOutT>>;
  using ConstPtr = std::shared_ptr<const SparsePatchInpainter<PointInT, PointOutT>>;
  using Base = GeometricCloudRepair<PointInT, PointOutT>;
  using Mode = typename Base::Mode;
  using PointCloudOut = pcl::PointCloud<PointOutT>;

  SparsePatchInpainter() = default;

  void setMode(Mode mode) { base_.setMode(mode); }
  Mode getMode() const { return base_.getMode(); }
  /** The geometric base, for its settings (noise, bandwidth, hole sizes, depth images, …). */
  Base& getGeometricRepair() { return base_; }
  const Base& getGeometricRepair() const { return base_; }
  [[deprecated("renamed getGeometricRepair")]] Base& getGeometricInpainter() { return base_; }
  [[deprecated("renamed getGeometricRepair")]] const Base& getGeometricInpainter() const { return base_; }

  /** The dictionary the patches are coded over (null, the default: a self-similar one). */
  void setDictionary(const PatchDictionary::ConstPtr& dictionary) { patch_options_.dictionary = dictionary; }
  PatchDictionary::ConstPtr getDictionary() const { return patch_options_.dictionary; }
  /** Auto (default): patches where the relief check measures them ahead; Always; Never (the base). */
  void setPatchDecision(PatchDecision decision)
  {
    patch_options_.decision.mode = decision;
    nonlocal_options_.decision.mode = decision;
  }
  PatchDecision getPatchDecision() const { return patch_options_.decision.mode; }
  void setPatchOptions(const CloudPatchOptions& options) { patch_options_ = options; }
  const CloudPatchOptions& getPatchOptions() const { return patch_options_; }
  /** The non-local stage of the denoising (its decision.mode is set by setPatchDecision too). */
  void setNonlocalPatchOptions(const NonlocalPatchOptions& options) { nonlocal_options_ = options; }
  const NonlocalPatchOptions& getNonlocalPatchOptions() const { return nonlocal_options_; }
  void setNumberOfThreads(int threads)
  {
    base_.setNumberOfThreads(threads);
    patch_options_.num_threads = threads;
    nonlocal_options_.num_threads = threads;
  }

  /** What the base did, and what the patch stage decided and did, in the last process(). */
  const CloudRepairReport& getReport() const { return base_.getReport(); }
  const CloudPatchReport& getPatchReport() const { return patch_report_; }
  /** The patch stage of the denoising (Denoise and DenoiseAndComplete modes). */
  const CloudPatchReport& getDenoisingPatchReport() const { return denoise_report_; }
  /** The non-local stage of the denoising (Denoise and DenoiseAndComplete modes). */
  const NonlocalPatchReport& getNonlocalPatchReport() const { return nonlocal_report_; }
  const pcl::Indices& getKeptIndices() const { return base_.getKeptIndices(); }
  const pcl::Indices& getAddedSources() const { return base_.getAddedSources(); }

protected:
  void performProcessing(PointCloudOut& output) override;

private:
  using pcl::CloudSurfaceProcessing<PointInT, PointOutT>::input_;
  using pcl::CloudSurfaceProcessing<PointInT, PointOutT>::indices_;

  Base base_;
  CloudPatchOptions patch_options_;
  CloudPatchReport patch_report_, denoise_report_;
  NonlocalPatchOptions nonlocal_options_;
  NonlocalPatchReport nonlocal_report_;
};

}  // namespace patchdict
}  // namespace pcl

#ifdef PCL_NO_PRECOMPILE
#include <pcl_patchdict/cloud/impl/sparse_patch_inpainter.hpp>
#endif
