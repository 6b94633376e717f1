// Non-local averaging of height-map patches on a point cloud (Digne 2012, "Similarity based filtering of
// point clouds"; Buades, Coll & Morel 2005, non-local means), decided per cloud by a coupled bootstrap.
#pragma once

#include <pcl_patchdict/repair/patch_decision.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

/** \brief Settings of the non-local patch averaging (lengths in point spacings s).
  *
  * Defaults: those of bench/denoise_probes.py nonlocal, measured in docs/results.md. */
struct NonlocalPatchOptions {
  /// Auto, the default, applies the average when the coupled bootstrap check measures it to lower the
  /// risk (decision.min_risk_reduction); Always applies it unchecked, Never returns the base.
  PatchDecisionOptions decision;
  int grid_size = 8;               ///< descriptor bins per side
  double bin_spacings = 1.5;       ///< descriptor bin side
  double kernel_bins = 0.6;        ///< Gaussian splat σ of a descriptor bin, in bins
  double fine_bin_spacings = 0.75; ///< bin side of the height grid that is averaged
  double fine_kernel_bins = 0.5;   ///< its splat σ, in its bins
  int dimensions = 24;             ///< PCA dimensions of the descriptor
  int neighbours = 64;             ///< nearest descriptors averaged (plus the query's own copies)
  /// Weight exp(−d²/h²), h² = bandwidth_factor × the expected squared distance of two noisy copies of
  /// one patch (2 × dimensions × the noise variance of a bin).
  double bandwidth_factor = 3.0;
  double self_weight = 1.0;        ///< weight of the query's own grid in the average
  /// With a blind spot: the point's own height and its blind average combined by their variances
  /// instead — own share a = v / (v + σ²), v the average's error variance (one per cloud: the mean
  /// squared miss of the blind averages against the points' own heights, less σ²). Off by default:
  /// better on the reliefs at k = 0.5, but the decision then applied it to a smooth dome where it is
  /// 1.21 × worse (docs/results.md).
  bool own_by_variance = false;
  double search_eps = 0.5;         ///< approximate nearest descriptors: within (1 + eps) × the true distance
  /// Blind spot: descriptor bins whose centres lie within this many spacings of the patch's own point
  /// are left out of the match, and the points within it out of the other bins, and no patch whose
  /// own point is within max(this, 3 fine kernels) is a match: a point's own noise then neither chooses
  /// nor makes its average (0: off, the probe's descriptors).
  double blind_radius = 0.5;
  /// Auto's check: the coupled bootstrap's α in [0.05, 2] — the check runs at noise σ√(1 + α²) and
  /// scores against a twin with noise σ√(1 + 1/α²) (see denoiseCloudNonlocally).
  double check_alpha = 0.5;
  std::uint64_t seed = 0;          ///< of the check's extra noise (same seed, same decision)
  /// Auto declines clouds of more points than this without running (0: no limit): on 2 cores the
  /// check costs 0.10–0.46 ms a point and the average 0.29–0.63 ms (docs/results.md).
  std::size_t max_checked_points = 200000;
  /// The check averages every k-th point only, k the smallest stride that leaves at most this many
  /// (all patches are still matched against): its time is then mostly the descriptors' (0: all points).
  std::size_t check_queries = 25000;
  std::size_t pca_sample = 20000;  ///< descriptors (evenly strided) the PCA basis is fitted on
  int num_threads = 0;             ///< 0: OpenMP's default
  /// Throws Error naming the first setting out of range.
  void check() const;
};

struct NonlocalPatchReport {
  PatchOutcome outcome = PatchOutcome::NotRun;
  std::string reason;
  /// Auto's check (input units): the estimated rms error of the base and of the non-local average at
  /// noise σ√(1 + α²), and the z of their paired difference per point (neighbouring points share
  /// matches: it overstates the significance); scored_points: the points they are means over.
  double base_error = 0.0, patch_error = 0.0, z = 0.0;
  std::size_t scored_points = 0;
  std::size_t moved_points = 0;
  double median_neighbours = 0.0;  ///< median effective number of averaged patches (Σw)²/Σw²
  double own_share = 0.0;          ///< own_by_variance: the share a of the point's own height
  double mean_correction = 0.0;    ///< mean |move| of the points (input units)
  double seconds_check = 0.0, seconds_apply = 0.0;
};

/** \brief Non-local means of height-map patches: every point moves along its patch's normal to the
  * weighted mean of similar patches' heights at its own place.
  *
  * Per point of `base` (the geometric denoiser's output, one per `noisy` point): a frame (weighted
  * centroid and PCA normal of the base within the patch, turned to the structure tensor of a weighted
  * quadric fit), a descriptor (grid_size² Gaussian splat of the noisy heights, empty bins at the mean
  * base height) in a PCA basis fitted over the descriptor, its 180° turn and its two mirror images with
  * negated heights, and a finer grid of the noisy heights. The `neighbours` nearest descriptors
  * (approximate kd-tree) weigh exp(−d²/h²); the point's new height is the weighted mean of their fine
  * grids read at its own place, with self_weight on its own grid. `spacing` ≤ 0: the mean
  * nearest-neighbour spacing of `base`. Ignores options.decision (see denoiseCloudNonlocally).
  * Deterministic whatever the thread count; throws Error for bad input or options. */
void averageSimilarPatches(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                           double spacing, double noise_sigma, const NonlocalPatchOptions& options,
                           std::vector<Eigen::Vector3d>& denoised, NonlocalPatchReport* report = nullptr);

/** \brief averageSimilarPatches behind the patch decision (options.decision.mode): Auto applies it when
  * a check measures it to help, Always applies it, Never returns the base.
  *
  * Auto's check is a coupled bootstrap (Oliveira, Lei & Tibshirani 2021; Pang et al. 2021's
  * recorrupted-to-recorrupted): with ω ~ N(0, noise_sigma²) along each point's normal (the base's
  * quadric at `bandwidth`, seeded by options.seed), y⁺ = y + αω and y⁻ = y − ω/α carry independent
  * noise. The base (the local quadrics at `bandwidth`) and the average over it both run on y⁺, and
  * their mean squared heights against y⁻, less σ²(1 + 1/α²), estimate their risks at noise σ√(1 + α²)
  * with no σ in their difference. The average applies when its risk is below the base's by
  * options.decision.min_risk_reduction (patchesLowerTheRisk); the check costs a second run of the
  * average. No `bandwidth` (0: the base has none, as under a depth law): Auto declines.
  * `denoised` gets one point per base point (the base when declined). */
void denoiseCloudNonlocally(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                            double spacing, double noise_sigma, double bandwidth, const NonlocalPatchOptions& options,
                            std::vector<Eigen::Vector3d>& denoised, NonlocalPatchReport* report = nullptr);

namespace detail {
/** The core of both. Patches: one per centre (a point on a base), with its own noisy point (whose
  * place in the patch the heights are read at), described from the data points around the centre: their
  * base positions `base` (the frame) and noisy ones `noisy` (the heights), one per data point. The
  * queries (indices of patches) are matched against the first `database` patches, their own excepted. */
struct NonlocalData {
  const std::vector<Eigen::Vector3d>& noisy;
  const std::vector<Eigen::Vector3d>& base;
  const std::vector<Eigen::Vector3d>& centres;
  const std::vector<Eigen::Vector3d>& owns;
  std::size_t database;
  const std::vector<std::size_t>& queries;
};
/** Per query: the centre and normal of its frame, the height of its own noisy point, of its centre,
  * the non-local estimate at its own place (heights along the normal from the frame's centre), the
  * effective number of averaged patches, and whether it had a patch (enough points around it). */
struct NonlocalHeights {
  std::vector<Eigen::Vector3d> centre, normal;
  std::vector<double> own, base_height, estimate, effective;
  /// The matches' weighted mean alone (no self term), and their summed weight W: with a blind spot the
  /// query's own noise entered neither, and estimate = (W·blind + self_weight·own) / (W + self_weight).
  std::vector<double> blind, weight;
  std::vector<char> valid;
  double own_share = -1.0;  ///< ≥ 0: estimate = own_share × own + (1 − own_share) × blind (own_by_variance)
};
void nonlocalHeights(const NonlocalData& data, double spacing, double noise_sigma, const NonlocalPatchOptions& options,
                     NonlocalHeights& heights);

/** averageSimilarPatches, returning the heights it moved the points by (one per query: points 0, stride,
  * 2·stride, …, matched against every patch; the other points keep the base). */
NonlocalHeights averageAndMove(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                               double spacing, double noise_sigma, const NonlocalPatchOptions& options,
                               std::vector<Eigen::Vector3d>& denoised, NonlocalPatchReport& report,
                               std::size_t stride = 1);

}  // namespace detail

}  // namespace patchdict
}  // namespace pcl
