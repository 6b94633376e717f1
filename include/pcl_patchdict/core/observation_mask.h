// ObservationMask — which entries of a matrix of signals (heights, one patch a column) were observed:
// the mask that patches, coding and the repairs pass along with their height matrices.
#pragma once

#include <Eigen/Core>

namespace pcl {
namespace patchdict {

/** Entry (i, j) true where row i of signal j was observed; an empty mask means every entry was. */
using ObservationMask = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

}  // namespace patchdict
}  // namespace pcl
