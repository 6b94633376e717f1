// An unorganised spinning-LiDAR scan whose points carry their beam (a `ring` field, as Velodyne,
// Ouster and Hesai drivers write it) put back on its beams × azimuth grid.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace pcl {
namespace patchdict {

/** Where each point of an unorganised scan sits in its sensor's grid. */
struct RingGrid {
  std::size_t width = 0, height = 0;  ///< azimuth steps of a turn, and beams (rings)
  double azimuth_start = 0.0, azimuth_step = 0.0;  ///< column c's azimuth start + c·step (radians)
  /// Per point: its pixel (row = ring, column = its azimuth step), or -1 when it has none (not
  /// finite, or a nearer point of the same ring took the pixel).
  std::vector<long long> pixel;
  std::size_t placed = 0, collisions = 0;
};

/** Organises a scan by ring: rows are the rings 0…beams−1, columns the azimuth steps of one turn
  * about the sensor's z axis (points in the sensor's frame). The step is the median positive
  * difference between consecutive azimuths within the rings (a whole turn of W = round(2π / step)
  * columns); column 0 starts at the smallest azimuth. Throws pcl::patchdict::Error when a ring is
  * outside [0, beams), beams is 0 or over 1024, fewer than 16 points are finite, or no step can be
  * found (every point of a ring at one azimuth). */
RingGrid organizeByRing(const std::vector<Eigen::Vector3d>& points, const std::vector<long long>& rings,
                        std::size_t beams);

}  // namespace patchdict
}  // namespace pcl
