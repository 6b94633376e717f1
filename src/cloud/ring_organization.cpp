// organizeByRing (ring_organization.h): an unorganised spinning-LiDAR scan back on its grid.
#include <pcl_patchdict/cloud/ring_organization.h>
#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace pcl {
namespace patchdict {

RingGrid organizeByRing(const std::vector<Eigen::Vector3d>& points, const std::vector<long long>& rings,
                        std::size_t beams)
{
  constexpr double kTurn = 2.0 * 3.14159265358979323846;
  if (rings.size() != points.size())
    throw Error("organizeByRing: " + std::to_string(rings.size()) + " rings for " + std::to_string(points.size()) +
                " points");
  if (beams == 0 || beams > 1024)
    throw Error("organizeByRing: " + std::to_string(beams) + " beams (1 to 1024)");
  RingGrid grid;
  grid.height = beams;
  std::vector<std::vector<double>> azimuths(beams);
  std::size_t finite = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (rings[i] < 0 || rings[i] >= static_cast<long long>(beams))
      throw Error("point " + std::to_string(i) + " has ring " + std::to_string(rings[i]) + ", outside 0.." +
                  std::to_string(beams - 1));
    const Eigen::Vector3d& p = points[i];
    if (!p.allFinite() || (p.x() == 0.0 && p.y() == 0.0))
      continue;
    azimuths[std::size_t(rings[i])].push_back(std::atan2(p.y(), p.x()));
    ++finite;
  }
  if (finite < 16)
    throw Error("organizeByRing: fewer than 16 measured points");
  std::vector<double> steps;
  double start = kTurn;
  for (auto& ring : azimuths) {
    std::sort(ring.begin(), ring.end());
    for (std::size_t k = 1; k < ring.size(); ++k)
      if (ring[k] > ring[k - 1])
        steps.push_back(ring[k] - ring[k - 1]);
    if (!ring.empty())
      start = std::min(start, ring.front());
  }
  if (steps.empty())
    throw Error("organizeByRing: no azimuth step (every ring's points at one azimuth)");
  std::nth_element(steps.begin(), steps.begin() + std::ptrdiff_t(steps.size() / 2), steps.end());
  const double step = steps[steps.size() / 2];
  const double columns = std::round(kTurn / step);
  if (!(columns >= 2.0) || columns > 1e6)
    throw Error("organizeByRing: an azimuth step of " + std::to_string(step) + " rad makes no grid");
  grid.width = static_cast<std::size_t>(columns);
  grid.azimuth_step = kTurn / columns;
  grid.azimuth_start = start;
  grid.pixel.assign(points.size(), -1);
  std::vector<double> taken(grid.width * grid.height, -1.0);  // the range of the point in each pixel
  std::vector<std::size_t> owner(grid.width * grid.height, 0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    if (!p.allFinite() || (p.x() == 0.0 && p.y() == 0.0))
      continue;
    double turns = (std::atan2(p.y(), p.x()) - start) / grid.azimuth_step;
    long long column = std::llround(turns) % static_cast<long long>(grid.width);
    column = column < 0 ? column + static_cast<long long>(grid.width) : column;
    const std::size_t pixel = std::size_t(rings[i]) * grid.width + std::size_t(column);
    const double range = p.norm();
    if (taken[pixel] >= 0.0) {
      ++grid.collisions;
      if (range >= taken[pixel])
        continue;
      grid.pixel[owner[pixel]] = -1;  // the nearer point takes the pixel (the farther was occluded)
    } else {
      ++grid.placed;
    }
    taken[pixel] = range;
    owner[pixel] = i;
    grid.pixel[i] = static_cast<long long>(pixel);
  }
  return grid;
}

}  // namespace patchdict
}  // namespace pcl
