// Unorganised spinning-LiDAR PCDs with a `ring` field (ring_scan.h).
#include "ring_scan.h"

#include <pcl_patchdict/cloud/range_image.h>
#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace pcl {
namespace patchdict {
namespace cli {


bool readRingScan(const CloudInput& input, RingScan& scan)
{
  const auto& cloud = *input.cloud;
  const pcl::PCLPointField* field = input.from_pcd ? findIntegerField(input.blob, "ring") : nullptr;
  if (cloud.height > 1 || !field)
    return false;
  const std::size_t n = cloud.size();
  std::vector<long long> rings(n);
  long long most = 0;
  for (std::size_t i = 0; i < n; ++i) {
    rings[i] = static_cast<long long>(readPointField(input.blob, i, *field));  // exact: ≤ 32-bit fields
    if (rings[i] < 0 || rings[i] > 1023)
      throw Error("point " + std::to_string(i) + " has ring " + std::to_string(rings[i]) +
                  ": a spinning LiDAR's rings are 0 to 1023");
    most = std::max(most, rings[i]);
  }
  std::vector<char> seen(static_cast<std::size_t>(most) + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    seen[std::size_t(rings[i])] = 1;
  const auto used = static_cast<long long>(std::count(seen.begin(), seen.end(), char(1)));
  if (used < 2)
    throw Error("every point is on ring " + std::to_string(most) +
                ": a single beam makes no grid to repair (a spinning LiDAR's scan has two or more)");
  if (2 * used < most + 1)
    throw Error("the rings run to " + std::to_string(most) + " but only " + std::to_string(used) +
                " of them hold points: ring values out of range");
  // The points in the sensor's frame (the cloud is shifted by its offset, its sensor origin too).
  const Eigen::Matrix3d R = cloud.sensor_orientation_.cast<double>().normalized().toRotationMatrix();
  const Eigen::Vector3d o = cloud.sensor_origin_.head<3>().cast<double>();
  std::vector<Eigen::Vector3d> local(n);
  for (std::size_t i = 0; i < n; ++i)
    local[i] = R.transpose() * (Eigen::Vector3d(cloud[i].x, cloud[i].y, cloud[i].z) - o);
  scan.grid = organizeByRing(local, rings, static_cast<std::size_t>(most) + 1);
  const std::size_t W = scan.grid.width, H = scan.grid.height;
  // The grid must be a spinning sensor's (else the scan is refused, not repaired as something else).
  std::vector<Eigen::Vector3d>& grid_points = scan.sensor_points;
  grid_points.assign(W * H, Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t i = 0; i < n; ++i)
    if (scan.grid.pixel[i] >= 0)
      grid_points[std::size_t(scan.grid.pixel[i])] = local[i];
  const SpinningSensorModel model = fitSpinningSensor(grid_points, W, H);
  if (!model.valid)
    throw Error("the scan's rings make a " + std::to_string(W) + " x " + std::to_string(H) +
                " grid that is no spinning sensor's: " + model.failure);
  scan.organised = std::make_shared<pcl::PointCloud<pcl::PointNormal>>(W, H);
  pcl::PointNormal empty;
  empty.x = empty.y = empty.z = std::numeric_limits<float>::quiet_NaN();
  std::fill(scan.organised->begin(), scan.organised->end(), empty);
  scan.organised->is_dense = false;
  scan.organised->sensor_origin_ = cloud.sensor_origin_;
  scan.organised->sensor_orientation_ = cloud.sensor_orientation_;
  scan.point_of_pixel.assign(W * H, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (scan.grid.pixel[i] >= 0) {
      (*scan.organised)[std::size_t(scan.grid.pixel[i])] = cloud[i];
      scan.point_of_pixel[std::size_t(scan.grid.pixel[i])] = static_cast<long long>(i);
    }
  return true;
}

void scatterRingRepair(const RingScan& scan, const CloudInput& input, const pcl::PointCloud<pcl::PointNormal>& repaired,
                       const pcl::Indices& filled, pcl::PointCloud<pcl::PointNormal>& out, pcl::Indices& records)
{
  const auto& cloud = *input.cloud;
  const std::size_t n = cloud.size(), W = scan.grid.width;
  out.clear();
  records.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const long long pixel = scan.grid.pixel[i];
    const bool repaired_here = pixel >= 0 && std::isfinite(repaired[std::size_t(pixel)].x);
    out.push_back(repaired_here ? repaired[std::size_t(pixel)] : cloud[i]);
    records.push_back(static_cast<pcl::index_t>(i));
  }
  for (const auto index : filled) {
    const std::size_t pixel = static_cast<std::size_t>(index), row = pixel / W, column = pixel % W;
    long long source = -1;
    for (std::size_t d = 1; d < W && source < 0; ++d)
      for (const std::size_t c : {(column + d) % W, (column + W - d) % W})
        if (source < 0 && scan.point_of_pixel[row * W + c] >= 0)
          source = scan.point_of_pixel[row * W + c];
    if (source < 0)
      continue;  // a ring without a placed point has no pixel to fill
    out.push_back(repaired[pixel]);
    records.push_back(static_cast<pcl::index_t>(source));
  }
  out.width = static_cast<std::uint32_t>(out.size());
  out.height = 1;
  out.is_dense = false;
}

}  // namespace cli
}  // namespace patchdict
}  // namespace pcl
