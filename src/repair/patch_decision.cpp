#include <pcl_patchdict/repair/patch_decision.h>

#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <cmath>

namespace pcl {
namespace patchdict {

const char* toString(PatchOutcome outcome)
{
  switch (outcome) {
  case PatchOutcome::Applied:
    return "applied";
  case PatchOutcome::Declined:
    return "declined";
  default:
    return "not run";
  }
}

void PatchDecisionOptions::check() const
{
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (probe_factors.empty() || !std::all_of(probe_factors.begin(), probe_factors.end(), positive))
    throw Error("patch decision: the probe factors must be > 0");
  if (!positive(probe_radius) || !positive(relief_gain))
    throw Error("patch decision: the probe radius and the relief gain must be > 0");
  if (!std::isfinite(min_improvement) || min_improvement < 0.0 || probe_max_seeds < 0 || !std::isfinite(quad_factor) ||
      quad_factor < 0.0)
    throw Error("patch decision: the minimum improvement, the probe's seeds and the quad factor must be ≥ 0");
  if (!std::isfinite(min_risk_reduction) || min_risk_reduction < 0.0 || min_risk_reduction >= 1.0)
    throw Error("patch decision: the minimum risk reduction must be in [0, 1)");
}

double PatchDecisionOptions::hiddenRadius(double d, double side) const
{
  // The probe hides a disc of the holes' radius (the loop's diameter d overstates it by the ring of
  // removed faces: measured 0.35 d ≈ the punched radius on the harness holes). Capped at 0.3 × the
  // patch side: a disc hiding nearly the whole patch says nothing about the surface (large holes:
  // the question is whether it is a relief, not how big the hole is).
  return std::min(probe_radius * d, 0.3 * side);
}

const PatchPredictionCheck* ReliefVerdict::shown() const
{
  const int side = significant_side >= 0 ? significant_side : any_side;
  return side >= 0 ? &checks[static_cast<std::size_t>(side)] : nullptr;
}

ReliefVerdict checkRelief(const std::vector<PatchSet>& sets, const std::vector<double>& sides, double d, double unit,
                          const PatchDecisionOptions& options, const PatchDictionary::ConstPtr& dictionary,
                          const PatchCorrectionParameters& parameters)
{
  if (sets.size() != sides.size())
    throw Error("relief check: one patch side per patch set");
  ReliefVerdict verdict;
  for (std::size_t i = 0; i < sets.size(); ++i) {
    const PatchPredictionCheck check =
        checkPatchPrediction(sets[i], options.hiddenRadius(d, sides[i]), dictionary, parameters, 10);
    verdict.checks.push_back(check);
    // A relief is where the dictionary predicts better by a margin that matters: the gain alone
    // would call a perfect sphere a relief (both errors near zero, their ratio large).
    const bool significant = check.biharmonic_rms - check.dictionary_rms >= options.min_improvement * unit;
    if (check.gain > verdict.best_any) {
      verdict.best_any = check.gain;
      verdict.any_side = static_cast<int>(i);
    }
    if (significant && check.gain > verdict.best_significant) {
      verdict.best_significant = check.gain;
      verdict.significant_side = static_cast<int>(i);
    }
  }
  return verdict;
}

bool patchesLowerTheRisk(double patch_risk, double base_risk, const PatchDecisionOptions& options)
{
  return patch_risk < (1.0 - options.min_risk_reduction) * base_risk;
}

}  // namespace patchdict
}  // namespace pcl
