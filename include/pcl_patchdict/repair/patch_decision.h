// PatchDecision — whether a repair's patch stage goes into its result: decided by measurement
// (each repair says what it measures), or forced either way.
#pragma once

namespace pcl {
namespace patchdict {

/** Whether the patch stage applies: Auto keeps it only when measured to help (holes: the relief
  * check; denoising: an estimate of the error with and without it), Always and Never force it. */
enum class PatchDecision { Auto, Always, Never };

}  // namespace patchdict
}  // namespace pcl
