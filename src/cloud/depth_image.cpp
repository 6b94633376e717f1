// Depth images of organised clouds (see depth_image.h).
#include <pcl_patchdict/cloud/depth_image.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

double median(std::vector<double>& values)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

bool usable(const Eigen::Vector3d& p) { return p.allFinite() && p.z() > 0.0; }

// One axis of the camera: pixel = f·ratio + c, robustly. Slopes between pixels a quarter of the image
// apart on one line (row for x, column for y), their median; then c as the median offset; then least
// squares over the points within max_reprojection of that line.
bool fitAxis(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height, bool along_columns,
             double typical, double max_reprojection, double& f, double& c)
{
  // A depth a thousand times off the median is no measurement, even on its ray (the principal
  // point's ray holds any depth): the fit never sees it.
  const auto usable = [typical](const Eigen::Vector3d& p) {
    return p.allFinite() && p.z() > 1e-3 * typical && p.z() < 1e3 * typical;
  };
  const std::size_t lines = along_columns ? height : width, length = along_columns ? width : height;
  const std::size_t gap = std::max<std::size_t>(1, length / 4);
  const auto index = [&](std::size_t line, std::size_t k) { return along_columns ? line * width + k : k * width + line; };
  const auto ratio = [&](std::size_t i) { return (along_columns ? points[i].x() : points[i].y()) / points[i].z(); };
  std::vector<double> slopes;
  const std::size_t line_step = std::max<std::size_t>(1, lines / 64), k_step = std::max<std::size_t>(1, length / 256);
  for (std::size_t line = 0; line < lines; line += line_step)
    for (std::size_t k = 0; k + gap < length; k += k_step) {
      const std::size_t i = index(line, k), j = index(line, k + gap);
      if (!usable(points[i]) || !usable(points[j]))
        continue;
      const double d = ratio(j) - ratio(i);
      if (std::abs(d) > 0.0 && std::isfinite(d))
        slopes.push_back(static_cast<double>(gap) / d);
    }
  if (slopes.size() < 8)
    return false;
  f = median(slopes);
  if (!std::isfinite(f) || f == 0.0)
    return false;
  std::vector<double> offsets;
  for (std::size_t line = 0; line < lines; line += line_step)
    for (std::size_t k = 0; k < length; k += k_step) {
      const std::size_t i = index(line, k);
      if (usable(points[i]))
        offsets.push_back(static_cast<double>(k) - f * ratio(i));
    }
  c = median(offsets);
  for (int round = 0; round < 2; ++round) {  // least squares over the inliers of the robust line
    double s1 = 0, sa = 0, sp = 0, saa = 0, sap = 0;
    for (std::size_t line = 0; line < lines; ++line)
      for (std::size_t k = 0; k < length; ++k) {
        const std::size_t i = index(line, k);
        if (!usable(points[i]))
          continue;
        const double a = ratio(i), p = static_cast<double>(k);
        if (!(std::abs(f * a + c - p) <= max_reprojection))
          continue;
        s1 += 1;
        sa += a;
        sp += p;
        saa += a * a;
        sap += a * p;
      }
    const double det = s1 * saa - sa * sa;
    if (s1 < 16 || !(std::abs(det) > 0.0))
      return false;
    f = (s1 * sap - sa * sp) / det;
    c = (sp - f * sa) / s1;
  }
  return std::isfinite(f) && std::isfinite(c) && f != 0.0;
}

}  // namespace

std::size_t DepthImage::measured() const { return static_cast<std::size_t>(std::count(valid.begin(), valid.end(), 1)); }

DepthImage makeDepthImage(const std::vector<Eigen::Vector3d>& points, std::size_t width, std::size_t height,
                          double max_reprojection)
{
  DepthImage image;
  image.width = width;
  image.height = height;
  image.depth.assign(width * height, std::numeric_limits<double>::quiet_NaN());
  image.valid.assign(width * height, 0);
  if (points.size() != width * height || width < 2 || height < 2)
    return image;
  std::vector<double> depths;
  for (const auto& p : points)
    if (usable(p))
      depths.push_back(p.z());
  const double typical = median(depths);
  if (!std::isfinite(typical))
    return image;
  PinholeCamera& camera = image.camera;
  if (!fitAxis(points, width, height, true, typical, max_reprojection, camera.fx, camera.cx) ||
      !fitAxis(points, width, height, false, typical, max_reprojection, camera.fy, camera.cy))
    return image;
  double squared = 0.0;
  std::size_t used = 0;
  for (std::size_t row = 0; row < height; ++row)
    for (std::size_t column = 0; column < width; ++column) {
      const std::size_t i = row * width + column;
      if (!points[i].allFinite())
        continue;
      const bool plausible = usable(points[i]) && points[i].z() < 1e3 * typical && points[i].z() > 1e-3 * typical;
      const Eigen::Vector2d error =
          plausible ? Eigen::Vector2d(camera.project(points[i]) - Eigen::Vector2d(column, row))
                    : Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
      if (!(error.cwiseAbs().maxCoeff() <= max_reprojection)) {
        ++camera.off_ray;
        continue;
      }
      squared += error.squaredNorm();
      ++used;
      image.depth[i] = points[i].z();
      image.valid[i] = 1;
    }
  camera.rms_pixels = used ? std::sqrt(squared / static_cast<double>(used)) : 0.0;
  camera.valid = used >= 16 && camera.rms_pixels <= 0.5 * max_reprojection;
  if (!camera.valid) {
    std::fill(image.depth.begin(), image.depth.end(), std::numeric_limits<double>::quiet_NaN());
    std::fill(image.valid.begin(), image.valid.end(), 0);
  }
  return image;
}

double DepthNoiseModel::sigma(double z) const { return coefficient * std::pow(std::abs(z), exponent); }

DepthNoiseModel estimateDepthNoise(const DepthImage& image, std::size_t stride)
{
  DepthNoiseModel model;
  const std::size_t W = image.width, H = image.height;
  stride = std::max<std::size_t>(1, stride);
  std::vector<double> depths, residuals;  // per sample: depth, |r| in depth units
  for (std::size_t row = 2; row + 2 < H; row += stride)
    for (std::size_t column = 2; column + 2 < W; column += stride) {
      const double zc = image.at(column, row);
      if (!image.valid[row * W + column])
        continue;
      // The plane q = a + b·du + c·dv through the measured neighbours (at least 16 of the 24, all
      // within 5 % of the centre's depth), its value a at the centre, and that prediction's
      // leverage h = (AᵀA)⁻¹₀₀: the residual's variance is σ²(1 + h).
      Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
      Eigen::Vector3d Atq = Eigen::Vector3d::Zero();
      int count = 0;
      bool planar = true;
      for (int dv = -2; dv <= 2 && planar; ++dv)
        for (int du = -2; du <= 2; ++du) {
          if (du == 0 && dv == 0)
            continue;
          const std::size_t i = (row + dv) * W + (column + du);
          if (!image.valid[i])
            continue;
          if (std::abs(image.depth[i] - zc) > 0.05 * zc) {
            planar = false;
            break;
          }
          const Eigen::Vector3d a(1.0, du, dv);
          AtA += a * a.transpose();
          Atq += a / image.depth[i];
          ++count;
        }
      if (!planar || count < 16)
        continue;
      const Eigen::Matrix3d inverse = AtA.inverse();
      const double predicted = (inverse * Atq)(0), leverage = inverse(0, 0);
      const double r = (1.0 / zc - predicted) * zc * zc / std::sqrt(1.0 + leverage);
      depths.push_back(zc);
      residuals.push_back(std::abs(r));
    }
  model.samples = depths.size();
  if (model.samples < 30)
    return model;
  std::vector<std::size_t> order(depths.size());
  for (std::size_t i = 0; i < order.size(); ++i)
    order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return depths[a] < depths[b]; });
  model.depth_low = depths[order[order.size() / 20]];
  model.depth_high = depths[order[order.size() - 1 - order.size() / 20]];
  if (model.depth_high >= 1.5 * model.depth_low && model.samples >= 600) {
    // Log-log slope of six equally filled depth bins' median |r| against their median depth.
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int bins = 0;
    for (int b = 0; b < 6; ++b) {
      std::vector<double> r, z;
      for (std::size_t k = order.size() * b / 6; k < order.size() * (b + 1) / 6; ++k) {
        r.push_back(residuals[order[k]]);
        z.push_back(depths[order[k]]);
      }
      const double mr = median(r), mz = median(z);
      if (!(mr > 0.0) || !(mz > 0.0))
        continue;
      sx += std::log(mz);
      sy += std::log(mr);
      sxx += std::log(mz) * std::log(mz);
      sxy += std::log(mz) * std::log(mr);
      ++bins;
    }
    const double det = bins * sxx - sx * sx;
    if (bins >= 4 && det > 1e-12) {
      model.exponent = std::clamp((bins * sxy - sx * sy) / det, 0.0, 3.0);
      model.exponent_fitted = true;
    }
  }
  // Quantised depths make many residuals exactly 0 (flat windows within one layer), so the median
  // |r| can vanish: a trimmed RMS instead — the lower 90 % of |r| / z^p, whose mean square is
  // 0.623 σ² for Gaussian noise (the variance of a normal truncated at ±1.645 σ).
  std::vector<double> scaled(residuals.size());
  for (std::size_t i = 0; i < residuals.size(); ++i)
    scaled[i] = residuals[i] / std::pow(depths[i], model.exponent);
  std::sort(scaled.begin(), scaled.end());
  const std::size_t kept = std::max<std::size_t>(1, scaled.size() * 9 / 10);
  double sum = 0.0;
  for (std::size_t i = 0; i < kept; ++i)
    sum += scaled[i] * scaled[i];
  model.coefficient = std::sqrt(sum / static_cast<double>(kept) / 0.623);
  return model;
}

FreeSpaceTest::FreeSpaceTest(const DepthImage& image, double spacing_factor, double relative_depth)
    : camera_(image.camera), width_(image.width), height_(image.height), spacing_factor_(spacing_factor),
      relative_depth_(relative_depth)
{
  const std::size_t W = image.width, H = image.height;
  nearest_.assign(W * H, std::numeric_limits<double>::infinity());
  for (std::size_t row = 0; row < H; ++row)
    for (std::size_t column = 0; column < W; ++column) {
      double m = std::numeric_limits<double>::infinity();
      for (std::size_t r = row ? row - 1 : 0; r <= std::min(H - 1, row + 1); ++r)
        for (std::size_t c = column ? column - 1 : 0; c <= std::min(W - 1, column + 1); ++c)
          if (image.valid[r * W + c])
            m = std::min(m, image.depth[r * W + c]);
      nearest_[row * W + column] = m;
    }
}

bool FreeSpaceTest::violates(const Eigen::Vector3d& p) const
{
  if (!camera_.valid || !p.allFinite() || !(p.z() > 0.0))
    return false;
  const Eigen::Vector2d pixel = camera_.project(p);
  const double column = std::round(pixel.x()), row = std::round(pixel.y());
  if (!(column >= 0.0 && row >= 0.0 && column < static_cast<double>(width_) && row < static_cast<double>(height_)))
    return false;
  const double seen = nearest_[static_cast<std::size_t>(row) * width_ + static_cast<std::size_t>(column)];
  if (!std::isfinite(seen))
    return false;
  const double tolerance = std::max(spacing_factor_ * camera_.pixelSpacing(seen), relative_depth_ * seen);
  return p.z() < seen - tolerance;
}

ViewpointFreeSpaceTest::ViewpointFreeSpaceTest(const std::vector<Eigen::Vector3d>& points,
                                               const Eigen::Vector3d& viewpoint, double spacing,
                                               double spacing_factor, double relative_range)
    : viewpoint_(viewpoint), spacing_(spacing), spacing_factor_(spacing_factor), relative_range_(relative_range)
{
  std::vector<double> ranges;
  for (const auto& p : points)
    if (p.allFinite() && (p - viewpoint).norm() > 0.0)
      ranges.push_back((p - viewpoint).norm());
  if (ranges.empty() || !(spacing > 0.0))
    return;
  // No wider than 0.7 of the samples' angular pitch (about 1/√2: no bin holds two neighbours, so a
  // bin's nearest range is one measurement's; wider bins let 45 of 12k fills through on mosd_learn0).
  bin_ = 0.7 * spacing / median(ranges);
  // Bins in azimuth and elevation about a pole across the mean view direction, so that the scan's
  // directions lie near the equator, where bins are squares (a pole along the view would crowd them).
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points)
    if (p.allFinite() && (p - viewpoint).norm() > 0.0)
      mean += (p - viewpoint).normalized();
  const Eigen::Vector3d forward = mean.norm() > 0.0 ? Eigen::Vector3d(mean.normalized()) : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d helper = std::abs(forward.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d side = helper.cross(forward).normalized();
  frame_.row(0) = forward.transpose();
  frame_.row(1) = side.transpose();
  frame_.row(2) = forward.cross(side).transpose();
  std::vector<std::pair<long long, double>> entries;
  for (const auto& p : points)
    if (p.allFinite() && (p - viewpoint).norm() > 0.0)
      entries.emplace_back(key(p), (p - viewpoint).norm());
  std::sort(entries.begin(), entries.end());
  for (const auto& e : entries)
    if (nearest_.empty() || nearest_.back().first != e.first)
      nearest_.push_back(e);  // the first of a key is its smallest range
}

long long ViewpointFreeSpaceTest::key(const Eigen::Vector3d& p) const
{
  const Eigen::Vector3d d = frame_ * (p - viewpoint_).normalized();
  const long long a = static_cast<long long>(std::floor((std::atan2(d.y(), d.x()) + M_PI) / bin_));
  const long long e = static_cast<long long>(std::floor((std::asin(std::clamp(d.z(), -1.0, 1.0)) + M_PI) / bin_));
  return a * 4000000LL + e;
}

bool ViewpointFreeSpaceTest::violates(const Eigen::Vector3d& p) const
{
  if (nearest_.empty() || !p.allFinite())
    return false;
  const double range = (p - viewpoint_).norm();
  if (!(range > 0.0))
    return false;
  const long long centre = key(p);
  double seen = std::numeric_limits<double>::infinity();
  for (long long da = -1; da <= 1; ++da)
    for (long long de = -1; de <= 1; ++de) {
      const long long k = centre + da * 4000000LL + de;
      const auto it = std::lower_bound(nearest_.begin(), nearest_.end(), std::make_pair(k, -1.0));
      if (it != nearest_.end() && it->first == k)
        seen = std::min(seen, it->second);
    }
  if (!std::isfinite(seen))
    return false;
  return range < seen - std::max(spacing_factor_ * spacing_ * seen / range, relative_range_ * seen);
}

}  // namespace patchdict
}  // namespace pcl
