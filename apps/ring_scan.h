// Unorganised spinning-LiDAR PCDs with a `ring` field: put on their beams × azimuth grid for the
// range-image repairs, and the repaired grid put back in the file's own point order.
#pragma once

#include "cloud_input.h"

#include <pcl_patchdict/cloud/ring_organization.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace pcl {
namespace patchdict {
namespace cli {

struct RingScan {
  RingGrid grid;
  pcl::PointCloud<pcl::PointNormal>::Ptr organised;  ///< the grid (NaN where no point), in the input's frame
  std::vector<long long> point_of_pixel;             ///< the input point in each pixel, or -1
  std::vector<Eigen::Vector3d> sensor_points;        ///< the grid in the sensor's frame (NaN where no point)
};

/** True when the input is an unorganised PCD with an integer `ring` field (then `scan` is filled).
  * The number of beams is the largest ring + 1. Error (one line) for a ring out of range (negative,
  * or over 1023) and whatever organizeByRing refuses. */
bool readRingScan(const CloudInput& input, RingScan& scan);

/** The repaired grid back in the input's order: every input point (its repaired position where it
  * had a pixel and the repair kept one, else as read), then each filled pixel, recorded as a copy of
  * the nearest placed point of its ring (its ring, time and other fields). `filled` holds the filled
  * pixels. */
void scatterRingRepair(const RingScan& scan, const CloudInput& input, const pcl::PointCloud<pcl::PointNormal>& repaired,
                       const pcl::Indices& filled, pcl::PointCloud<pcl::PointNormal>& out, pcl::Indices& records);

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
