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
  // Rows in parallel; their squared errors are added in row order afterwards (the same bits on
  // any number of threads).
  std::vector<double> row_squared(height, 0.0);
  std::size_t used = 0, off_ray = 0;
#pragma omp parallel for schedule(static) reduction(+ : used, off_ray)
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
        ++off_ray;
        continue;
      }
      row_squared[row] += error.squaredNorm();
      ++used;
      image.depth[i] = points[i].z();
      image.valid[i] = 1;
    }
  camera.off_ray = off_ray;
  double squared = 0.0;
  for (const double row : row_squared)
    squared += row;
  camera.rms_pixels = used ? std::sqrt(squared / static_cast<double>(used)) : 0.0;
  camera.valid = used >= 16 && camera.rms_pixels <= 0.5 * max_reprojection;
  if (!camera.valid) {
    std::fill(image.depth.begin(), image.depth.end(), std::numeric_limits<double>::quiet_NaN());
    std::fill(image.valid.begin(), image.valid.end(), 0);
  }
  return image;
}

double DepthNoiseModel::sigma(double z) const { return coefficient * std::pow(std::abs(z), exponent); }

namespace {

// One noise sample per planar 5 × 5 window centred on a measured pixel of row `row` (every
// `stride`-th column): the depth and |r| of its centre (see estimateDepthNoise). `full` is (AᵀA)⁻¹ of
// a window with all 24 neighbours, which every such window shares.
void noiseSamplesOfRow(const DepthImage& image, std::size_t row, std::size_t stride, const Eigen::Matrix3d& full,
                       std::vector<std::pair<double, double>>& samples)
{
  const std::size_t W = image.width;
  for (std::size_t column = 2; column + 2 < W; column += stride) {
    const double zc = image.depth[row * W + column];
    if (!image.valid[row * W + column])
      continue;
    // The plane q = a + b·du + c·dv through the measured neighbours (at least 16 of the 24, all
    // within 5 % of the centre's depth), its value a at the centre, and that prediction's
    // leverage h = (AᵀA)⁻¹₀₀: the residual's variance is σ²(1 + h). AᵀA's entries are sums of small
    // integers (exact in any order); Aᵀq is summed in the window's order.
    double s1 = 0, su = 0, sv = 0, suu = 0, suv = 0, svv = 0, q0 = 0, q1 = 0, q2 = 0;
    int count = 0;
    bool planar = true;
    for (int dv = -2; dv <= 2 && planar; ++dv) {
      const char* valid = image.valid.data() + (row + dv) * W + column;
      const double* depth = image.depth.data() + (row + dv) * W + column;
      for (int du = -2; du <= 2; ++du) {
        if ((du == 0 && dv == 0) || !valid[du])
          continue;
        const double d = depth[du];
        if (std::abs(d - zc) > 0.05 * zc) {
          planar = false;
          break;
        }
        s1 += 1.0, su += du, sv += dv, suu += du * du, suv += du * dv, svv += dv * dv;
        q0 += 1.0 / d;
        q1 += du / d;
        q2 += dv / d;
        ++count;
      }
    }
    if (!planar || count < 16)
      continue;
    Eigen::Matrix3d inverse = full;
    if (count != 24) {
      Eigen::Matrix3d AtA;
      AtA << s1, su, sv, su, suu, suv, sv, suv, svv;
      inverse = AtA.inverse();
    }
    const Eigen::Vector3d Atq(q0, q1, q2);
    const double predicted = (inverse * Atq)(0), leverage = inverse(0, 0);
    const double r = (1.0 / zc - predicted) * zc * zc / std::sqrt(1.0 + leverage);
    samples.emplace_back(zc, std::abs(r));
  }
}

}  // namespace

DepthNoiseModel estimateDepthNoise(const DepthImage& image, std::size_t stride)
{
  DepthNoiseModel model;
  const std::size_t H = image.height;
  stride = std::max<std::size_t>(1, stride);
  Eigen::Matrix3d full_AtA = Eigen::Matrix3d::Zero();
  for (int dv = -2; dv <= 2; ++dv)
    for (int du = -2; du <= 2; ++du)
      if (du != 0 || dv != 0) {
        const Eigen::Vector3d a(1.0, du, dv);
        full_AtA += a * a.transpose();
      }
  const Eigen::Matrix3d full = full_AtA.inverse();
  // Rows in parallel, their samples joined in row order: the same samples in the same order on
  // any number of threads.
  const std::size_t rows = H > 4 ? (H - 5) / stride + 1 : 0;
  std::vector<std::vector<std::pair<double, double>>> per_row(rows);
#pragma omp parallel for schedule(dynamic, 8)
  for (std::size_t k = 0; k < rows; ++k)
    noiseSamplesOfRow(image, 2 + k * stride, stride, full, per_row[k]);
  std::vector<double> depths, residuals;  // per sample: depth, |r| in depth units
  for (const auto& row : per_row)
    for (const auto& [z, r] : row) {
      depths.push_back(z);
      residuals.push_back(r);
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
  const long count = static_cast<long>(scaled.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < count; ++i)
    scaled[i] = residuals[i] / std::pow(depths[i], model.exponent);
  // Sorted in two halves at once, then merged: sorted doubles are one sequence, however sorted.
  const auto middle = scaled.begin() + count / 2;
#pragma omp parallel sections
  {
#pragma omp section
    std::sort(scaled.begin(), middle);
#pragma omp section
    std::sort(middle, scaled.end());
  }
  std::inplace_merge(scaled.begin(), middle, scaled.end());
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
  if (W == 0 || H == 0 || image.depth.size() != W * H || image.valid.size() != W * H)
    return;
  // The 3 × 3 minimum as a minimum over 3 columns, then over 3 rows (the same values): each thread
  // keeps the column minima of its last three rows.
  const long rows = static_cast<long>(H);
  const auto across = [&](std::size_t row, double* out, double* measured) {
    const std::size_t o = row * W;
    const double inf = std::numeric_limits<double>::infinity();
    for (std::size_t column = 0; column < W; ++column) {  // NaN is never a minimum: as unmeasured
      const double z = image.depth[o + column];
      measured[column] = image.valid[o + column] && z == z ? z : inf;
    }
    out[0] = W > 1 ? std::min(measured[0], measured[1]) : measured[0];
    for (std::size_t column = 1; column + 1 < W; ++column)
      out[column] = std::min(std::min(measured[column - 1], measured[column]), measured[column + 1]);
    if (W > 1)
      out[W - 1] = std::min(measured[W - 2], measured[W - 1]);
  };
#pragma omp parallel
  {
    std::vector<double> band(3 * W), measured(W);
    long ready = -2;  // band holds rows ready − 1 … ready + 1, row r at (r mod 3)
#pragma omp for schedule(static)
    for (long r = 0; r < rows; ++r) {
      for (long k = std::max(r - 1, ready + 2); k <= std::min(rows - 1, r + 1); ++k)
        across(static_cast<std::size_t>(k), band.data() + static_cast<std::size_t>(k % 3) * W, measured.data());
      ready = r;
      const std::size_t row = static_cast<std::size_t>(r);
      const double* above = band.data() + ((row ? row - 1 : row) % 3) * W;
      const double* here = band.data() + (row % 3) * W;
      const double* below = band.data() + (std::min(H - 1, row + 1) % 3) * W;
      double* out = nearest_.data() + row * W;
      for (std::size_t column = 0; column < W; ++column)
        out[column] = std::min(std::min(above[column], here[column]), below[column]);
    }
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
  return nearerThanSeen(p.z(), nearest_[static_cast<std::size_t>(row) * width_ + static_cast<std::size_t>(column)]);
}

bool FreeSpaceTest::violatesAt(std::size_t i, double z) const
{
  if (!camera_.valid || !(z > 0.0) || !std::isfinite(z) || i >= nearest_.size())
    return false;
  return nearerThanSeen(z, nearest_[i]);
}

bool FreeSpaceTest::nearerThanSeen(double z, double seen) const
{
  if (!std::isfinite(seen))
    return false;
  const double tolerance = std::max(spacing_factor_ * camera_.pixelSpacing(seen), relative_depth_ * seen);
  return z < seen - tolerance;
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
