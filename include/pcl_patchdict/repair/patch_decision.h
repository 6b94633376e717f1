// The patch decision — whether a repair's patch stage goes into its result, decided by measurement or
// forced — in one place for the mesh repairs and the cloud path: its options, its outcome, the relief
// check over candidate patch sides and the risk comparison of denoising.
#pragma once

#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>
#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/repair/patch_prediction_check.h>

#include <vector>

namespace pcl {
namespace patchdict {

/** Whether the patch stage applies: Auto keeps it only when measured to help (holes: the relief
  * check; denoising: an estimate of the error with and without it), Always forces it, Never runs
  * the geometric base alone. (Mesh holes and missing vertices always keep their patches unless
  * Never: there the relief check chooses the hole repair's settings, HoleSettings.) */
enum class PatchDecision { Auto, Always, Never };

/** What happened to the patch stage: not run (nothing to correct), applied, or declined (measured not
  * to help, or Never). */
enum class PatchOutcome { NotRun, Applied, Declined };

/** "not run", "applied" or "declined": the outcome's word in reports and --json. */
const char* toString(PatchOutcome outcome);

/** \brief The measured decision's settings, shared by the mesh repairs (HoleRepairOptions,
  * DenoiseOptions through PatchRepairCommon) and the cloud path (CloudPatchOptions).
  *
  * Lengths are relative: d is the median diameter of the filled holes, and the length unit `unit`
  * is the mesh's mean edge or the cloud's point spacing. The defaults are the mesh repairs'; the cloud
  * path sets its own measured ones (CloudPatchOptions). */
struct PatchDecisionOptions {
  PatchDecision mode = PatchDecision::Auto;
  /// Holes, the relief check: patch sides probe_factors × d are tried; at each, a hidden disc of
  /// radius probe_radius × d (at most 0.3 × the side) is predicted by the dictionary and by a
  /// biharmonic fill (checkPatchPrediction). A side counts when the dictionary's rms is below the
  /// fill's by at least min_improvement × unit; a relief needs a counted gain ≥ relief_gain.
  std::vector<double> probe_factors{0.8, 1.2, 1.6};
  double probe_radius = 0.35;
  double relief_gain = 1.3;       ///< (why this value: docs/results.md)
  double min_improvement = 0.1;
  /// The check uses an evenly spaced subset of at most this many seeds (0: all).
  int probe_max_seeds = 600;
  /// Patches as wide as the holes see their rim: L ≥ quad_factor × d on meshes (0: no minimum), L =
  /// quad_factor × d on clouds (> 0 there). Why these values: docs/results.md.
  double quad_factor = 0.6;
  /// Denoising, Auto: the patches apply when their estimated squared error is below the base's by at
  /// least this fraction.
  double min_risk_reduction = 0.05;
  /// Throws Error naming the first setting out of range.
  void check() const;
  /// The hidden disc's radius for holes of diameter d at patch side `side`.
  double hiddenRadius(double d, double side) const;
};

/** \brief The relief check over candidate patch sides: the prediction check at each side, the best
  * gain among the sides that count (significant) and the best of all. */
struct ReliefVerdict {
  std::vector<PatchPredictionCheck> checks;  ///< one per side, in the order given
  double best_significant = 0.0, best_any = 0.0;
  int significant_side = -1, any_side = -1;  ///< their indices (−1: none)
  /// The gain a report shows: the best significant one, else the best of all (0: nothing measured).
  double gain() const { return best_significant > 0.0 ? best_significant : best_any; }
  /// The check a report shows: at the best significant side, else at the best side.
  const PatchPredictionCheck* shown() const;
  /// A relief: a significant gain of at least options.relief_gain.
  bool relief(const PatchDecisionOptions& options) const { return best_significant >= options.relief_gain; }
};

/** Runs checkPatchPrediction on each of `sets` (patches of side sides[i], holes of diameter d),
  * hiding options.hiddenRadius(d, sides[i]), and keeps the best gains; a side is significant when the
  * dictionary's rms is below the fill's by options.min_improvement × unit. */
ReliefVerdict checkRelief(const std::vector<PatchSet>& sets, const std::vector<double>& sides, double d, double unit,
                          const PatchDecisionOptions& options, const PatchDictionary::ConstPtr& dictionary,
                          const PatchCorrectionParameters& parameters);

/** Denoising's measured decision: the patches' estimated squared error is below the base's by at
  * least options.min_risk_reduction of it. */
bool patchesLowerTheRisk(double patch_risk, double base_risk, const PatchDecisionOptions& options);

}  // namespace patchdict
}  // namespace pcl
