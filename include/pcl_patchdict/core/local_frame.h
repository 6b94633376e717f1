// Local reference frames in double precision, the form every stage passes them in: a frame is an
// Eigen::Matrix3d whose rows are its X, Y, Z axes (local = R·(p − s), world = s + Rᵀ·local), a
// list of frames a std::vector<Eigen::Matrix3d> (one per seed), as PatchSet::rotations.
// pcl::ReferenceFrame appears only at the PCL boundary (pcl/reference_frame.h).
#pragma once

#include <Eigen/Core>

namespace pcl {
namespace patchdict {

/** Every entry rounded to the nearest float and back to double — bit for bit what a round trip
  * through pcl::ReferenceFrame's float[3] axes gives (fromReferenceFrame(toReferenceFrame(frame))).
  *
  * Frames are rounded once where they are made (computeQuadFrames, the layout's
  * coverage seeds, frameFromNormal, the codec's coverage frames), where they used to pass through
  * pcl::ReferenceFrame: the height maps are measured in the rounded frame, so outputs stay the
  * bytes they were, and version-3 .pdc files, whose decoder re-derives the same frames, decode
  * byte-identically. Rounding a rounded frame changes nothing. */
Eigen::Matrix3d roundToSinglePrecision(const Eigen::Matrix3d& frame);

/** \brief What a patch covers: p lies in the r-ball of the seed, inside the patch's square (side √2·r)
  * in its frame, and its normal (zero if unknown) does not face away from the frame's Z. `local`, if
  * given, receives p in the frame. The one test of the patch mapping (PatchMeshReconstruction), the
  * layout's coverage seeds and the patch correction, so all agree on what a patch covers. */
bool patchContains(const Eigen::Vector3d& seed, const Eigen::Matrix3d& rotation, double radius,
                   const Eigen::Vector3d& p, const Eigen::Vector3d& normal, Eigen::Vector3d* local = nullptr);

}  // namespace patchdict
}  // namespace pcl
