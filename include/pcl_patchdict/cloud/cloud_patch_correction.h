// The patch stage of the cloud path (Sarkar et al. 2017, sections 3–5, on points): a geometric hole
// fill's new points, or a geometric denoiser's output, moved onto sparse-coded patches.
#pragma once

#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/repair/patch_decision.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pcl {
namespace patchdict {

struct CloudPatchOptions {
  CloudPatchOptions()
  {
    decision.quad_factor = 0.8;  // L = 0.8 d: every patch over a hole sees its rim (the mesh repair's relief setting)
    decision.probe_max_seeds = 1500;
  }
  /// The measured decision (shared with the mesh repairs): the relief check for holes, with the
  /// point spacing as its length unit, L = decision.quad_factor × d (d the median diameter of the
  /// filled holes) and the patch side the best of decision.probe_factors × d; the cross-validated
  /// risk for denoising.
  PatchDecisionOptions decision;
  /// A dictionary of grid_size × grid_size atoms learned elsewhere (e.g. from clean scans of the
  /// same kind); null: a self-similar one, learned from the cloud's own fully observed patches.
  PatchDictionary::ConstPtr dictionary;
  /// N, bins per side: 0 = the dictionary's, or else the even N whose bin is about bin_spacings
  /// × s on the middle probe side, within [16, 48] (a relief's walls need bins of a few spacings).
  int grid_size = 0;
  double bin_spacings = 3.0;
  /// A bin's height: the biweight-weighted mean of the input points within this many bins of its
  /// centre (random samples leave no bin of an observed patch empty).
  double bin_reach = 1.0;
  int sparsity = 0;  ///< atoms per code; 0 = N / 2 (8 at 16 × 16, as the mesh repairs)
  int overlap = 3;  ///< k of the layout: 4k offset seeds per quad
  /// The coarse shape for the layout is made from at most this many points (evenly strided): it
  /// only has to be right at the scale of L, and Poisson's time grows with the points.
  std::size_t layout_points = 10000;
  /// Weight of staying at the fill, relative to the patches' point-to-plane terms.
  double fidelity = 0.01;
  /// Denoising: no hole sizes the patches, so d = denoise_scale × s.
  double denoise_scale = 40.0;
  /// Denoising: a code stops once its rms misfit over the observed bins is ≤ error_factor × σ /
  /// √(points a bin averages).
  double error_factor = 1.0;
  int num_threads = 0;
  std::uint64_t seed = 0;
};

struct CloudPatchReport {
  PatchOutcome outcome = PatchOutcome::NotRun;  ///< declined: why in `reason`
  std::string reason;
  std::size_t holes = 0;         ///< connected groups of ≥ 10 new points
  double hole_diameter = 0.0;    ///< d, median over the groups (input units)
  double spacing = 0.0;          ///< s used (input units)
  double quad_length = 0.0, patch_side = 0.0;  ///< input units
  int grid_size = 0;             ///< N used
  double gain = 0.0;             ///< the check's best (significant) gain: biharmonic rms / dictionary rms
  double dictionary_rms = 0.0, biharmonic_rms = 0.0;  ///< at that side (input units)
  std::size_t test_patches = 0;
  bool self_similar = false;
  std::size_t patches = 0, patches_used = 0;
  std::size_t moved_points = 0;  ///< new points with at least one patch over them
  double mean_correction = 0.0;  ///< mean |moved − fill| over the moved points (input units)
  /// Denoising: the base's estimated rms error (Stein's risk at its bandwidth) and the patches'
  /// cross-validated one, which decided (input units).
  double base_error = 0.0, patch_error = 0.0;
  double seconds_layout = 0.0, seconds_check = 0.0, seconds_patches = 0.0;
};

/** \brief Moves the new points of a geometric hole fill onto the cloud's patches.
  *
  *  1. The new points are grouped into holes (linked within 3 s); d = the median group diameter.
  *  2. A layout (coarse shape by Poisson + Laplacian smoothing → quads → frames) of L = decision.quad_factor·d
  *     over the input and new points together; seeds moved along their Z onto the points.
  *  3. Heights binned from the input points only: the new points' bins are unobserved.
  *  4. The relief check (checkRelief, the mesh repairs' own): a disc hidden in the fully observed
  *     patches, predicted by masked OMP over the dictionary and by a biharmonic fill of the grid; the
  *     patches apply (Auto) when the dictionary's rms is below the fill's by decision.relief_gain and
  *     by decision.min_improvement × s. Smooth surfaces tie, and then the geometric fill is kept.
  *  5. Masked OMP completes every patch over a hole; each new point x0 moves by the δ minimising
  *     Σ w (n·(x0 + δ − p))² + fidelity·Σw·|δ|² over the patches whose square holds it (p the
  *     coded surface at x0's tangent coordinates, n its normal, w its confidence).
  *
  * `observed` are the input points, `added` the fill's; `spacing` s (input units; ≤ 0: the mean
  * nearest-neighbour spacing of `observed`). `corrected` receives one position per added point
  * (the fill itself when the patches are declined). Deterministic for a given input, options and
  * seed, whatever the thread count. Throws Error for fewer than 100 observed points, non-finite
  * positions or bad options. */
void correctCloudFillWithPatches(const std::vector<Eigen::Vector3d>& observed, const std::vector<Eigen::Vector3d>& added,
                                 double spacing, const CloudPatchOptions& options,
                                 std::vector<Eigen::Vector3d>& corrected, CloudPatchReport* report = nullptr);

/** \brief Denoising by patches (K-SVD denoising on the surface, Elad & Aharon 2006, in the paper's
  * patches): the same stage as correctCloudFillWithPatches with d = denoise_scale × s, heights
  * binned from the `noisy` points, the layout and targets the geometric `base` (one denoised point
  * per noisy one), codes stopping at the noise level σ. Auto decides by measurement: patches from
  * the even points predict the odd ones (two-fold cross-validation), and their squared error (the
  * mean squared miss less σ²) must be below `base_risk`, the base's estimated mean squared error
  * (≤ 0: unknown, and the base is kept). The relief check is not the test here: a dictionary can
  * predict a hidden relief better than a smooth fill and still denoise worse than local quadrics.
  * `corrected` gets one position per base point (the base itself when declined). */
void denoiseCloudWithPatches(const std::vector<Eigen::Vector3d>& noisy, const std::vector<Eigen::Vector3d>& base,
                             double spacing, double noise_sigma, double base_risk, const CloudPatchOptions& options,
                             std::vector<Eigen::Vector3d>& corrected, CloudPatchReport* report = nullptr);

/** Throws Error when an option is out of range. */
void checkCloudPatchOptions(const CloudPatchOptions& options);

}  // namespace patchdict
}  // namespace pcl
