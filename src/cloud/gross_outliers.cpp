// Gross outliers (see gross_outliers.h).
#include <pcl_patchdict/cloud/gross_outliers.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {

std::size_t removeGrossOutliers(std::vector<Eigen::Vector3d>& points, double factor)
{
  std::vector<std::size_t> finite;
  for (std::size_t i = 0; i < points.size(); ++i)
    if (points[i].allFinite())
      finite.push_back(i);
  if (finite.size() < 2)
    return 0;
  // At most ~100k evenly spaced samples for the quantiles: the same for the same input.
  const std::size_t stride = std::max<std::size_t>(1, finite.size() / 100000);
  // The three axes' quantiles side by side (each its own samples): the same values on any thread count.
  Eigen::Vector3d median, extent;
#pragma omp parallel for schedule(static, 1)
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    values.reserve(finite.size() / stride + 1);
    for (std::size_t k = 0; k < finite.size(); k += stride)
      values.push_back(points[finite[k]][axis]);
    // The median first; the quartiles then lie in its lower and upper parts (nth_element leaves them
    // partitioned there), so each is selected from half the values: the same values, a third of the work.
    const auto index = [&](double q) { return static_cast<std::ptrdiff_t>(q * static_cast<double>(values.size() - 1)); };
    const auto mid = values.begin() + index(0.5), low = values.begin() + index(0.25), high = values.begin() + index(0.75);
    std::nth_element(values.begin(), mid, values.end());
    median[axis] = *mid;
    std::nth_element(values.begin(), low, mid);
    std::nth_element(mid, high, values.end());
    extent[axis] = *high - *low;
  }
  const double reach = factor * std::max(extent.maxCoeff(), 1e-12 * std::max(median.cwiseAbs().maxCoeff(), 1.0));
  std::size_t removed = 0;
  const long long count = static_cast<long long>(finite.size());
#pragma omp parallel for schedule(static) reduction(+ : removed)
  for (long long k = 0; k < count; ++k) {
    Eigen::Vector3d& p = points[finite[static_cast<std::size_t>(k)]];
    if (!((p - median).cwiseAbs().maxCoeff() <= reach)) {
      p.setConstant(std::numeric_limits<double>::quiet_NaN());
      ++removed;
    }
  }
  return removed;
}

std::vector<std::size_t> firstCopies(const std::vector<Eigen::Vector3d>& points)
{
  std::vector<std::size_t> first(points.size()), order;
  for (std::size_t i = 0; i < points.size(); ++i) {
    first[i] = i;
    if (points[i].allFinite())
      order.push_back(i);
  }
  const auto less = [&](std::size_t a, std::size_t b) {
    const Eigen::Vector3d &p = points[a], &q = points[b];
    if (p.x() != q.x())
      return p.x() < q.x();
    if (p.y() != q.y())
      return p.y() < q.y();
    if (p.z() != q.z())
      return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t k = 1; k < order.size(); ++k)
    if (points[order[k]] == points[order[k - 1]])
      first[order[k]] = first[order[k - 1]];
  return first;
}

}  // namespace patchdict
}  // namespace pcl
