// checkPatchPrediction — does a dictionary predict a hidden part of this surface better than smooth
// geometry does? The measurement that tells a relief (patches win) from a smooth scan (they tie).
#pragma once

#include <pcl_patchdict/repair/patch_correction.h>
#include <pcl_patchdict/coding/patch_dictionary.h>
#include <pcl_patchdict/patches/patch_set.h>

#include <cstddef>

namespace pcl {
namespace patchdict {

struct PatchPredictionCheck {
  double gain = 0.0;  ///< biharmonic rms / dictionary rms (> 1: the dictionary predicts better; 0: no evidence)
  double dictionary_rms = 0.0, biharmonic_rms = 0.0;
  std::size_t test_patches = 0, hidden_bins = 0;
};

/** \brief Cross-validated on the fully observed patches of `patches`: a central disc of radius
  * `hidden_radius` (same units as the patches) is hidden in each test patch and predicted (a) by
  * masked OMP over `dictionary` — or, if null, over a self-similar dictionary learned
  * (PatchCorrection::learnSelfSimilar) from the other half of the patches — and (b) by the
  * biharmonic fill of the grid (min Σ (Δh)² with the visible bins fixed: the patch-domain analogue of
  * Liepa's fairing); the hole repair's relief check (its gains on smooth and relief scans:
  * docs/results.md). Fewer than `min_test_patches` usable test patches, or a disc covering no bin
  * or every bin, gives gain 0. */
PatchPredictionCheck checkPatchPrediction(const PatchSet& patches, double hidden_radius,
                                          const PatchDictionary::ConstPtr& dictionary,
                                          const PatchCorrectionParameters& parameters,
                                          std::size_t min_test_patches = 20);

}  // namespace patchdict
}  // namespace pcl
