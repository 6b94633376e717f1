// estimateRangeNoise (range_image.h): the range noise law of a spinning LiDAR from planar 3 × 5
// windows of its own scan, and the step its ranges are stored in.
#include "cloud/range_plane.h"

#include <pcl_patchdict/cloud/range_image.h>

#include <algorithm>
#include <complex>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

constexpr double kPi = 3.14159265358979323846;

// 1.4826 × the median |value|: σ for Gaussian noise, and robust to the residuals of structure
// (vegetation, edges, grazing ground) that a line along the beam does not fit.
double robustSigma(std::vector<double> values)
{
  if (values.empty())
    return 0.0;
  for (double& v : values)
    v = std::abs(v);
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return 1.4826 * *mid;
}

// The largest step q (0.1 mm to 64 mm, in metres; the steps sensors store ranges in) on which the
// ranges sit, or 0. A range stored in steps of q also sits on q/2, q/5…: the largest wins.
double rangeQuantum(const RangeImage& image)
{
  static const double steps_mm[] = {0.1, 0.2, 0.25, 0.5, 1, 2, 2.5, 4, 5, 8, 10, 16, 20, 32, 50, 64};
  double found = 0.0;
  for (const double mm : steps_mm) {
    const double q = 1e-3 * mm;
    std::complex<double> sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < image.range.size(); i += 7)
      if (image.valid[i]) {
        sum += std::polar(1.0, 2.0 * kPi * image.range[i] / q);
        ++count;
      }
    if (count >= 100 && std::abs(sum) / double(count) > 0.5)
      found = q;
  }
  return found;
}

}  // namespace

RangeNoiseModel estimateRangeNoise(const RangeImage& image, std::size_t stride)
{
  RangeNoiseModel law;
  const std::size_t W = image.width, H = image.height;
  stride = std::max<std::size_t>(1, stride);
  const double step = std::abs(image.model.azimuth_step);
  std::vector<double> residuals, ranges;
  for (std::size_t b = 0; b < H; b += 1)
    for (std::size_t c = (b % stride); c < W; c += stride) {
      const std::size_t i = b * W + c;
      if (!image.valid[i] || (!image.model.wraps && (c < 3 || c + 3 >= W)))
        continue;
      const double r0 = image.range[i];
      // Along the beam a plane is 1/ρ = A·cos δ + B·sin δ + C over the azimuth offset δ: in the
      // basis (1, sin δ / step, (1 − cos δ) / step²), well conditioned.
      detail::InverseRangePlane plane;
      std::size_t used = 0;
      for (int dc = -3; dc <= 3; ++dc) {
        const std::size_t j = b * W + (c + W + dc) % W;
        if (dc == 0 || !image.valid[j] || std::abs(image.range[j] - r0) > 0.05 * r0)
          continue;
        const double delta = dc * step;
        const Eigen::Vector3d x(1.0, std::sin(delta) / step, (1.0 - std::cos(delta)) / (step * step));
        plane.add(x, 1.0 / image.range[j], 1.0);
        ++used;
      }
      Eigen::Vector3d w = Eigen::Vector3d::Zero();
      if (used < 5 || !plane.solve(w) || !(w(0) > 0.0))
        continue;
      // Leverage of the centre's prediction: x0ᵀ A⁻¹ x0 with x0 = (1, 0, 0).
      const double leverage = plane.centreLeverage();
      residuals.push_back((r0 - 1.0 / w(0)) / std::sqrt(1.0 + leverage));
      ranges.push_back(r0);
    }
  law.samples = residuals.size();
  law.quantum = rangeQuantum(image);
  if (residuals.size() < 20)
    return law;
  std::vector<double> sorted = ranges;
  std::sort(sorted.begin(), sorted.end());
  law.range_low = sorted[sorted.size() / 20];
  law.range_high = sorted[sorted.size() * 19 / 20];
  if (law.range_high >= 2.0 * law.range_low && residuals.size() >= 600) {
    // Six bins of equal count: log σ against log ρ.
    std::vector<std::size_t> order(ranges.size());
    for (std::size_t k = 0; k < order.size(); ++k)
      order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ranges[a] < ranges[b]; });
    double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
    for (int bin = 0; bin < 6; ++bin) {
      std::vector<double> r, rho;
      for (std::size_t k = order.size() * bin / 6; k < order.size() * (bin + 1) / 6; ++k) {
        r.push_back(residuals[order[k]]);
        rho.push_back(ranges[order[k]]);
      }
      std::nth_element(rho.begin(), rho.begin() + static_cast<std::ptrdiff_t>(rho.size() / 2), rho.end());
      const double x = std::log(rho[rho.size() / 2]), y = std::log(std::max(robustSigma(r), 1e-12));
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
    }
    const double slope = (6.0 * sxy - sx * sy) / (6.0 * sxx - sx * sx);
    if (std::isfinite(slope)) {
      law.exponent = std::clamp(slope, 0.0, 2.0);
      law.exponent_fitted = true;
    }
  }
  std::vector<double> scaled;
  for (std::size_t k = 0; k < residuals.size(); ++k)
    scaled.push_back(residuals[k] / std::pow(ranges[k], law.exponent));
  law.coefficient = robustSigma(scaled);
  return law;
}

}  // namespace patchdict
}  // namespace pcl
