// A spinning LiDAR's range image: fitting the beams and azimuth steps, the range noise law, the
// free-space bound (range_image.h).
#include <pcl_patchdict/cloud/range_image.h>
#include <pcl_patchdict/core/error.h>

#include <Eigen/Dense>

#include <algorithm>
#include <utility>
#include <complex>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

constexpr double kPi = 3.14159265358979323846;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

double wrapAngle(double a)
{
  a = std::fmod(a + kPi, 2.0 * kPi);
  return a < 0.0 ? a + kPi : a - kPi;
}

double median(std::vector<double> v)
{
  if (v.empty())
    return kNaN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Circular median of angles: the median of their offsets from their circular mean.
double circularMedian(const std::vector<double>& angles)
{
  if (angles.empty())
    return kNaN;
  std::complex<double> sum = 0.0;
  for (const double a : angles)
    sum += std::polar(1.0, a);
  const double mean = std::arg(sum);
  std::vector<double> offsets;
  offsets.reserve(angles.size());
  for (const double a : angles)
    offsets.push_back(wrapAngle(a - mean));
  return wrapAngle(mean + median(offsets));
}

// The beams' lines z = t·h + c (h the horizontal distance), robustly: least squares, then again over
// the points within 3 MADs. A beam whose points span too little h keeps c = 0 and t the median ratio.
void fitBeamLine(const std::vector<Eigen::Vector2d>& hz, double& t, double& c)
{
  std::vector<double> ratios;
  for (const auto& q : hz)
    ratios.push_back(q.y() / q.x());
  t = median(ratios);
  c = 0.0;
  std::vector<double> hs;
  for (const auto& q : hz)
    hs.push_back(q.x());
  const double h_med = median(hs);
  double spread = 0.0;
  for (const double h : hs)
    spread += (h - h_med) * (h - h_med);
  if (hz.size() < 8 || std::sqrt(spread / static_cast<double>(hz.size())) < 0.05 * h_med)
    return;
  std::vector<char> use(hz.size(), 1);
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    Eigen::Vector2d b = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < hz.size(); ++i)
      if (use[i]) {
        const Eigen::Vector2d row(hz[i].x(), 1.0);
        A += row * row.transpose();
        b += row * hz[i].y();
      }
    const Eigen::Vector2d x = A.ldlt().solve(b);
    if (!x.allFinite())
      return;
    t = x(0);
    c = x(1);
    std::vector<double> residuals;
    for (const auto& q : hz)
      residuals.push_back(std::abs(q.y() - t * q.x() - c));
    const double mad = median(residuals);
    for (std::size_t i = 0; i < hz.size(); ++i)
      use[i] = residuals[i] <= 3.0 * 1.4826 * mad + 1e-12;
  }
}

// Beam-origin circle (radius d, height z0) and per-beam elevations from the rows' points.
bool fitElevations(const std::vector<Eigen::Vector3d>& points, SpinningSensorModel& m)
{
  const std::size_t W = m.width, H = m.height;
  std::vector<double> t(H, kNaN), c(H, kNaN);
  std::vector<std::vector<Eigen::Vector2d>> rows(H);
  for (std::size_t b = 0; b < H; ++b) {
    for (std::size_t col = 0; col < W; ++col) {
      const Eigen::Vector3d& p = points[b * W + col];
      const double h = std::hypot(p.x(), p.y());
      if (p.allFinite() && h > 0.0)
        rows[b].emplace_back(h, p.z());
    }
    if (rows[b].size() >= 2)
      fitBeamLine(rows[b], t[b], c[b]);
  }
  // c_b = z0 − d·t_b over the beams with a line (d, z0 by least squares when the slopes spread).
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d y = Eigen::Vector2d::Zero();
  std::size_t lines = 0;
  double t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
  for (std::size_t b = 0; b < H; ++b)
    if (std::isfinite(t[b]) && c[b] != 0.0) {
      const Eigen::Vector2d row(1.0, -t[b]);
      A += row * row.transpose();
      y += row * c[b];
      ++lines;
      t_lo = std::min(t_lo, t[b]);
      t_hi = std::max(t_hi, t[b]);
    }
  if (lines >= 3 && t_hi - t_lo > 0.05) {
    const Eigen::Vector2d x = A.ldlt().solve(y);
    if (x.allFinite()) {
      m.beam_height = x(0);
      m.beam_radius = x(1);
    }
  }
  m.elevation.assign(H, kNaN);
  for (std::size_t b = 0; b < H; ++b) {
    std::vector<double> e;
    for (const auto& q : rows[b])
      if (q.x() - m.beam_radius > 0.0)
        e.push_back(std::atan2(q.y() - m.beam_height, q.x() - m.beam_radius));
    m.elevation[b] = median(e);
  }
  // Beams without a point (all sky) take their elevation from their neighbours, evenly.
  std::vector<std::size_t> known;
  for (std::size_t b = 0; b < H; ++b)
    if (std::isfinite(m.elevation[b]))
      known.push_back(b);
  if (known.empty())
    return false;
  for (std::size_t b = 0; b < H; ++b) {
    if (std::isfinite(m.elevation[b]))
      continue;
    const auto hi = std::lower_bound(known.begin(), known.end(), b);
    if (known.size() < 2)
      return false;
    const std::size_t b1 = hi == known.begin() ? known[0] : hi == known.end() ? known[known.size() - 2] : *(hi - 1);
    const std::size_t b2 = hi == known.begin() ? known[1] : hi == known.end() ? known.back() : *hi;
    const double slope = (m.elevation[b2] - m.elevation[b1]) / (double(b2) - double(b1));
    m.elevation[b] = m.elevation[b1] + slope * (double(b) - double(b1));
  }
  return true;
}

// Azimuth step (median neighbour step) and per-beam offsets (circular medians).
bool fitAzimuths(const std::vector<Eigen::Vector3d>& points, SpinningSensorModel& m)
{
  const std::size_t W = m.width, H = m.height;
  std::vector<double> az(W * H, kNaN), steps;
  for (std::size_t i = 0; i < W * H; ++i)
    if (points[i].allFinite() && std::hypot(points[i].x(), points[i].y()) > m.beam_radius)
      az[i] = std::atan2(points[i].y(), points[i].x());
  for (std::size_t b = 0; b < H; ++b)
    for (std::size_t col = 0; col + 1 < W; ++col)
      if (std::isfinite(az[b * W + col]) && std::isfinite(az[b * W + col + 1]))
        steps.push_back(wrapAngle(az[b * W + col + 1] - az[b * W + col]));
  if (steps.size() < 8 || W < 2)
    return false;
  m.azimuth_step = median(steps);
  if (!(std::abs(m.azimuth_step) > 1e-9) || std::abs(m.azimuth_step) * double(W) > 2.0 * kPi * 1.05)
    return false;
  m.wraps = std::abs(std::abs(m.azimuth_step) * double(W) - 2.0 * kPi) <= std::abs(m.azimuth_step);
  // A whole turn to 0.1 %: the step is exactly 2π / W (the median's error would add up over W
  // columns). A frame of a little more or less than a turn (a Velodyne's column count varies from
  // frame to frame) keeps the measured step.
  if (std::abs(std::abs(m.azimuth_step) * double(W) - 2.0 * kPi) <= 1e-3 * 2.0 * kPi)
    m.azimuth_step = std::copysign(2.0 * kPi / double(W), m.azimuth_step);
  std::vector<double> beam_start(H, kNaN), all;
  for (std::size_t b = 0; b < H; ++b) {
    std::vector<double> a;
    for (std::size_t col = 0; col < W; ++col)
      if (std::isfinite(az[b * W + col]))
        a.push_back(wrapAngle(az[b * W + col] - double(col) * m.azimuth_step));
    beam_start[b] = circularMedian(a);
    if (std::isfinite(beam_start[b]))
      all.push_back(beam_start[b]);
  }
  m.azimuth_start = circularMedian(all);
  m.azimuth_offset.assign(H, 0.0);
  for (std::size_t b = 0; b < H; ++b)
    if (std::isfinite(beam_start[b]))
      m.azimuth_offset[b] = wrapAngle(beam_start[b] - m.azimuth_start);
  return true;
}

// A point against its pixel's ray (direction u, unit, from `origin`): its range along the ray, and
// the tangents of the angles it lies off it in azimuth and in elevation (the offset's parts along the
// azimuth's and the elevation's directions over that range). inverse_cos: 1 / cos of the beam's
// elevation (u's horizontal length). The one off-ray test of the fit and of the image.
struct RayOffset {
  double along, azimuth, elevation;
};

RayOffset rayOffset(const Eigen::Vector3d& p, const Eigen::Vector3d& origin, const Eigen::Vector3d& u, double inverse_cos)
{
  const Eigen::Vector3d q = p - origin;
  const double along = q.dot(u);
  const Eigen::Vector3d e_az(-u.y() * inverse_cos, u.x() * inverse_cos, 0.0);
  const Eigen::Vector3d e_el = e_az.cross(u);  // towards the elevation's increase (or its opposite)
  return {along, q.dot(e_az) / along, q.dot(e_el) / along};
}

std::vector<double> inverseCosines(const SpinningSensorModel& m)
{
  std::vector<double> inverse_cos(m.height);
  for (std::size_t b = 0; b < m.height; ++b)
    inverse_cos[b] = 1.0 / std::cos(m.elevation[b]);
  return inverse_cos;
}

// The tolerance of the off-ray test: half an azimuth step, half the gap to the nearest beam.
Eigen::Vector2d rayTolerance(const SpinningSensorModel& m)
{
  return {0.5 * std::abs(m.azimuth_step), m.height > 1 ? 0.5 * m.beamGap() : 0.5 * std::abs(m.azimuth_step)};
}

// Whether each row's points lie at one elevation (seen from the beam-origin circle), apart from the
// other rows': the rows are some spinning sensor's beams, whatever their order and columns.
bool rowsAreBeams(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& m)
{
  std::vector<double> spreads, levels;
  for (std::size_t b = 0; b < m.height; ++b) {
    std::vector<double> offsets;
    for (std::size_t c = 0; c < m.width; ++c) {
      const Eigen::Vector3d& p = points[b * m.width + c];
      const double h = std::hypot(p.x(), p.y()) - m.beam_radius;
      if (p.allFinite() && h > 0.0)
        offsets.push_back(std::abs(std::atan2(p.z() - m.beam_height, h) - m.elevation[b]));
    }
    if (offsets.size() < 8)
      continue;
    spreads.push_back(median(offsets));
    levels.push_back(m.elevation[b]);
  }
  if (levels.size() < 2)
    return false;
  std::sort(levels.begin(), levels.end());
  std::vector<double> gaps;
  for (std::size_t k = 1; k < levels.size(); ++k)
    gaps.push_back(levels[k] - levels[k - 1]);
  return median(spreads) < 0.25 * median(gaps);
}

}  // namespace

double SpinningSensorModel::beamGap() const
{
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t b = 0; b + 1 < elevation.size(); ++b)
    gap = std::min(gap, std::abs(elevation[b + 1] - elevation[b]));
  return gap;
}

std::size_t RangeImage::measured() const
{
  return static_cast<std::size_t>(std::count(valid.begin(), valid.end(), char(1)));
}

SpinningSensorModel fitSpinningSensor(const std::vector<Eigen::Vector3d>& points, std::size_t width,
                                      std::size_t height)
{
  SpinningSensorModel m;
  m.width = width;
  m.height = height;
  const auto fail = [&](const std::string& why) {
    m.valid = false;
    m.failure = why;
    return m;
  };
  if (width * height != points.size() || width < 2)
    return fail("the grid is " + std::to_string(width) + " x " + std::to_string(height) + " for " +
                std::to_string(points.size()) + " points");
  std::size_t finite = 0;
  for (const auto& p : points)
    finite += p.allFinite() && std::hypot(p.x(), p.y()) > 0.0 ? 1 : 0;
  if (finite < 16)
    return fail("fewer than 16 measured points");
  if (!fitElevations(points, m))
    return fail("no beam has a measured point");
  m.rows_are_beams = rowsAreBeams(points, m);
  for (std::size_t b = 0; b + 2 < height; ++b)
    if ((m.elevation[b + 1] - m.elevation[b]) * (m.elevation[b + 2] - m.elevation[b + 1]) <= 0.0)
      return fail("the rows' elevations are not monotonic (rows " + std::to_string(b) + "-" + std::to_string(b + 2) +
                  "): the beams are out of order");
  if (height == 2 && m.elevation[0] == m.elevation[1])
    return fail("two rows at one elevation: rows are not beams");
  if (!fitAzimuths(points, m))
    return fail("the columns are not azimuth steps of a turn");
  // Every point against its ray: a beam's spread, the off-ray share, the RMS angle.
  const Eigen::Vector2d tolerance = rayTolerance(m);
  const double tan_az = std::tan(tolerance.x()), tan_el = std::tan(tolerance.y());
  const std::shared_ptr<const SpinningRays> rays = spinningRays(m);
  const std::vector<double> inverse_cos = inverseCosines(m);
  double squares = 0.0;
  std::size_t used = 0;
  std::vector<double> spread(height, 0.0);
  std::vector<std::size_t> count(height, 0);
  for (std::size_t b = 0; b < height; ++b)
    for (std::size_t col = 0; col < width; ++col) {
      const std::size_t i = b * width + col;
      if (!isReturn(points[i]))
        continue;
      const RayOffset off = rayOffset(points[i], rays->origin[i], rays->direction[i], inverse_cos[b]);
      if (!(off.along > 0.0) || std::abs(off.azimuth) > tan_az || std::abs(off.elevation) > tan_el) {
        ++m.off_ray;
        continue;
      }
      const double azimuth = std::atan(off.azimuth), elevation = std::atan(off.elevation);
      squares += azimuth * azimuth + elevation * elevation;
      spread[b] += elevation * elevation;
      ++count[b];
      ++used;
    }
  if (m.off_ray * 10 > finite)
    return fail(std::to_string(m.off_ray) + " of " + std::to_string(finite) +
                " points lie off the rays of a spinning sensor's grid");
  for (std::size_t b = 0; b < height && height > 1; ++b)
    if (count[b] >= 8 && std::sqrt(spread[b] / double(count[b])) > m.beamGap() / 3.0)
      return fail("row " + std::to_string(b) + " spreads over its neighbours' elevations: rows are not beams");
  m.rms_radians = used ? std::sqrt(squares / double(used)) : 0.0;
  m.valid = true;
  return m;
}

std::shared_ptr<const SpinningRays> spinningRays(const SpinningSensorModel& model)
{
  const std::size_t W = model.width, H = model.height;
  std::vector<double> column_cos(W), column_sin(W);
  for (std::size_t c = 0; c < W; ++c) {
    const double a = model.azimuth_start + static_cast<double>(c) * model.azimuth_step;
    column_cos[c] = std::cos(a);
    column_sin[c] = std::sin(a);
  }
  auto rays = std::make_shared<SpinningRays>();
  rays->direction.resize(W * H);
  rays->origin.resize(W * H);
  for (std::size_t b = 0; b < H; ++b) {
    const double oc = std::cos(model.azimuth_offset[b]), os = std::sin(model.azimuth_offset[b]);
    const double ec = std::cos(model.elevation[b]), es = std::sin(model.elevation[b]);
    for (std::size_t c = 0; c < W; ++c) {
      const double ca = column_cos[c] * oc - column_sin[c] * os, sa = column_sin[c] * oc + column_cos[c] * os;
      rays->direction[b * W + c] = Eigen::Vector3d(ec * ca, ec * sa, es);
      rays->origin[b * W + c] = Eigen::Vector3d(model.beam_radius * ca, model.beam_radius * sa, model.beam_height);
    }
  }
  return rays;
}

RangeImage makeRangeImage(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& model)
{
  if (!model.valid)
    throw Error("no spinning-sensor model: " + model.failure);
  return makeRangeImage(points, model, spinningRays(model));
}

RangeImage makeRangeImage(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& model,
                          const std::shared_ptr<const SpinningRays>& rays)
{
  if (!model.valid)
    throw Error("no spinning-sensor model: " + model.failure);
  if (points.size() != model.width * model.height)
    throw Error("the frame's grid (" + std::to_string(points.size()) + " points) is not the sensor model's " +
                std::to_string(model.width) + " x " + std::to_string(model.height));
  if (!rays || rays->direction.size() != points.size() || rays->origin.size() != points.size())
    throw Error("the rays given are not the sensor model's");
  RangeImage image;
  image.width = model.width;
  image.height = model.height;
  image.model = model;
  image.model.off_ray = 0;
  const std::size_t n = points.size();
  image.range.assign(n, kNaN);
  image.valid.assign(n, 0);
  image.rays = rays;
  const std::vector<double> inverse_cos = inverseCosines(model);
  const Eigen::Vector2d tolerance = rayTolerance(model);
  const double tan_az = std::tan(tolerance.x()), tan_el = std::tan(tolerance.y());
  // A range beyond 1000 × (or below 1/1000 of) the frame's typical one is no measurement (a
  // coordinate no sensor measured), as for a depth image; the typical range from ~4k points.
  std::vector<double> sample;
  for (std::size_t i = 0; i < n; i += std::max<std::size_t>(1, n / 4096))
    if (isReturn(points[i]))
      sample.push_back((points[i] - rays->origin[i]).norm());
  std::nth_element(sample.begin(), sample.begin() + std::ptrdiff_t(sample.size() / 2), sample.end());
  const double typical = sample.empty() ? 0.0 : sample[sample.size() / 2];
  const double far = typical > 0.0 ? 1000.0 * typical : std::numeric_limits<double>::infinity(), near = typical / 1000.0;
  std::size_t finite = 0, off = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = points[i];
    if (!isReturn(p))
      continue;
    ++finite;
    const RayOffset offset = rayOffset(p, rays->origin[i], rays->direction[i], inverse_cos[i / model.width]);
    const double along = offset.along;
    if (!(along > near) || !(along < far) || std::abs(offset.azimuth) > tan_az || std::abs(offset.elevation) > tan_el) {
      ++off;
      continue;
    }
    image.range[i] = along;
    image.valid[i] = 1;
  }
  image.model.off_ray = off;
  if (off * 10 > finite)
    throw Error("the frame does not fit the sensor model: " + std::to_string(off) + " of " + std::to_string(finite) +
                " points lie off the model's rays (a frame of another sensor?)");
  return image;
}

double RangeNoiseModel::sigma(double range) const
{
  const double law = coefficient * std::pow(std::max(range, 1e-12), exponent);
  return std::max(law, quantum / std::sqrt(12.0));
}

namespace {

// The minimum of `value` over each pixel's 3 × 3 neighbourhood (with the pixel itself when `self`),
// the azimuth wrapping when the model does: a pass over the beams above and below, then one over the
// columns either side, rows in parallel (each output depends on the input alone).
std::vector<double> neighbourhoodMinimum(const std::vector<double>& value, const RangeImage& image, bool self)
{
  const std::size_t W = image.width, H = image.height;
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> across(W * H, inf), column(W * H, inf), nearest(W * H, inf);
  const long long rows = static_cast<long long>(H);
#pragma omp parallel for schedule(static)
  for (long long row = 0; row < rows; ++row) {
    const std::size_t b = static_cast<std::size_t>(row);
    for (std::size_t c = 0; c < W; ++c) {
      double best = inf;  // the beams above and below
      if (b > 0)
        best = std::min(best, value[(b - 1) * W + c]);
      if (b + 1 < H)
        best = std::min(best, value[(b + 1) * W + c]);
      across[b * W + c] = self ? std::min(best, value[b * W + c]) : best;
      column[b * W + c] = std::min(best, value[b * W + c]);
    }
  }
#pragma omp parallel for schedule(static)
  for (long long row = 0; row < rows; ++row) {
    const std::size_t b = static_cast<std::size_t>(row);
    for (std::size_t c = 0; c < W; ++c) {
      double best = across[b * W + c];  // then the columns either side, with their own pixel
      if (c > 0)
        best = std::min(best, column[b * W + c - 1]);
      else if (image.model.wraps)
        best = std::min(best, column[b * W + W - 1]);
      if (c + 1 < W)
        best = std::min(best, column[b * W + c + 1]);
      else if (image.model.wraps)
        best = std::min(best, column[b * W]);
      nearest[b * W + c] = best;
    }
  }
  return nearest;
}

}  // namespace

std::vector<double> nearestMeasuredRange(const RangeImage& image)
{
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> measured(image.range.size(), inf);
  for (std::size_t i = 0; i < measured.size(); ++i)
    if (image.valid[i])
      measured[i] = image.range[i];
  return neighbourhoodMinimum(measured, image, false);
}

OriginFreeSpace::OriginFreeSpace(const RangeImage& image, double spacing_factor, double relative_range)
    : image_(image), spacing_factor_(spacing_factor), relative_range_(relative_range)
{
  const std::size_t W = image.width, H = image.height;
  const double inf = std::numeric_limits<double>::infinity();
  // |point| per measured pixel, then its minimum over each pixel's 3 × 3 neighbourhood.
  std::vector<double> norm(W * H, inf);
  for (std::size_t i = 0; i < W * H; ++i)
    if (image.valid[i])
      norm[i] = image.pointAt(i, image.range[i]).norm();
  nearest_ = neighbourhoodMinimum(norm, image, true);
  descending_ = H < 2 || image.model.elevation[0] > image.model.elevation[H - 1];
  for (const double e : image.model.elevation)
    tangent_.push_back(std::tan(e));
  // The offset |o| turns a point's direction from the origin by at most asin(|o| / |p|) from its ray.
  const double offset = std::hypot(image.model.beam_radius, image.model.beam_height);
  const double half_step = 0.5 * std::min(std::abs(image.model.azimuth_step), H > 1 ? image.model.beamGap() : 1.0);
  const double far = offset > 0.0 ? 1.25 * offset / std::sin(std::min(half_step, 1.0)) : 0.0;
  far_squared_ = far * far;
}

bool OriginFreeSpace::violates(const Eigen::Vector3d& p, std::size_t own) const
{
  const SpinningSensorModel& m = image_.model;
  const std::size_t W = m.width, H = m.height;
  // Far from the sensor the beam origins' offset turns no direction by half a step: its own pixel.
  if (p.squaredNorm() > far_squared_)
    return false;
  const double h = std::hypot(p.x(), p.y());
  if (!(h > 0.0))
    return false;
  // The beam nearest the point's elevation from the origin (tangents are monotonic over the rows).
  const double t = p.z() / h;
  std::size_t lo = 0, hi = H - 1;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    ((tangent_[mid] > t) == descending_ ? lo : hi) = mid;
  }
  const std::size_t b = std::abs(tangent_[lo] - t) <= std::abs(tangent_[hi] - t) ? lo : hi;
  // Its column: the point's azimuth from its own pixel's, in steps, with the beams' offsets.
  const std::size_t own_b = own / W, own_c = own % W;
  const Eigen::Vector3d& u = image_.direction(own);
  const double horizontal = std::hypot(u.x(), u.y());
  const double across = (u.x() * p.y() - u.y() * p.x()) / horizontal, along = (u.x() * p.x() + u.y() * p.y()) / horizontal;
  const double turn = std::atan2(across, along) + m.azimuth_offset[own_b] - m.azimuth_offset[b];
  long long c = static_cast<long long>(own_c) + std::llround(turn / m.azimuth_step);
  if (m.wraps)
    c = ((c % static_cast<long long>(W)) + static_cast<long long>(W)) % static_cast<long long>(W);
  else if (c < 0 || c >= static_cast<long long>(W))
    return false;
  const std::size_t i = b * W + static_cast<std::size_t>(c);
  if (i == own || !std::isfinite(nearest_[i]))
    return false;
  const double d = nearest_[i];
  const double tolerance = std::max(spacing_factor_ * d * std::abs(m.azimuth_step), relative_range_ * d);
  return p.norm() < d - tolerance;
}

void interpolateAtFilledPixels(std::vector<double>& values, const std::vector<char>& measured, std::size_t width,
                               std::size_t height, bool wraps, const std::vector<std::size_t>& filled)
{
  const long long W = static_cast<long long>(width), H = static_cast<long long>(height);
  std::vector<double> result(filled.size());
  for (std::size_t k = 0; k < filled.size(); ++k) {
    const long long b = static_cast<long long>(filled[k]) / W, c = static_cast<long long>(filled[k]) % W;
    double sum = 0.0, weights = 0.0;
    for (const auto& [db, dc] : {std::pair<int, int>{0, 1}, {0, -1}, {1, 0}, {-1, 0}})
      for (long long d = 1; d < std::max(W, H); ++d) {
        const long long bb = b + d * db;
        long long cc = c + d * dc;
        if (wraps)
          cc = ((cc % W) + W) % W;
        if (bb < 0 || bb >= H || cc < 0 || cc >= W || (dc != 0 && d >= W))
          break;
        const std::size_t j = static_cast<std::size_t>(bb * W + cc);
        if (measured[j]) {
          sum += values[j] / double(d);
          weights += 1.0 / double(d);
          break;
        }
      }
    result[k] = weights > 0.0 ? sum / weights : values[filled[k]];
  }
  for (std::size_t k = 0; k < filled.size(); ++k)  // after: a filled pixel never reads another's new value
    values[filled[k]] = result[k];
}

}  // namespace patchdict
}  // namespace pcl
