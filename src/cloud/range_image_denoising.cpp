// denoiseRangeImage (range_image_repair.h): robust local planes in 1/ρ over the ray directions of a
// window along the beams, each pixel moved on its own ray.
#include "cloud/range_plane.h"

#include <pcl_patchdict/cloud/range_image_repair.h>
#include <pcl_patchdict/core/error.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <omp.h>

namespace pcl {
namespace patchdict {

namespace {

struct Neighbour {
  Eigen::Vector3d x;   // basis coordinates of its ray
  double inverse, range, spatial, distance;
};

double tukey(double r)
{
  if (std::abs(r) >= 1.0)
    return 0.0;
  const double t = 1.0 - r * r;
  return t * t;
}

// The new range of pixel i, or NaN when it keeps its own (too few neighbours, degenerate plane).
double denoisePixel(const RangeImage& image, const RangeDenoisingParameters& p, const std::vector<double>& spatial,
                    double sigma, std::size_t i, std::vector<Neighbour>& window)
{
  const std::size_t W = image.width, H = image.height;
  const std::size_t b = i / W, c = i % W;
  const double r0 = image.range[i], step = std::abs(image.model.azimuth_step);
  const detail::RayBasis basis(image.direction[i], step);
  window.clear();
  const int R = p.column_radius, B = p.beam_radius;
  for (int db = -B; db <= B; ++db) {
    if ((db < 0 && b < std::size_t(-db)) || b + db >= H)
      continue;
    for (int dc = -R; dc <= R; ++dc) {
      if (!image.model.wraps && ((dc < 0 && c < std::size_t(-dc)) || c + dc >= W))
        continue;
      const std::size_t j = (b + db) * W + (c + W + dc) % W;
      if (!image.valid[j])
        continue;
      const double range = image.range[j];
      window.push_back({basis.coordinates(image.direction[j]), 1.0 / range, range,
                        spatial[std::size_t((db + B) * (2 * R + 1) + (dc + R))], std::hypot(double(dc), double(db))});
    }
  }
  const double band = p.range_sigmas * sigma;
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  bool have = false;
  for (int pass = 0; pass <= p.refinements; ++pass) {
    detail::InverseRangePlane plane;
    int supported = 0;
    for (const Neighbour& q : window) {
      double weight;
      if (pass == 0) {
        const double allowed = band + p.slope_allowance * q.distance * r0 * step;
        weight = tukey((q.range - r0) / allowed);
      } else {
        const double predicted = 1.0 / w.dot(q.x);
        weight = predicted > 0.0 ? tukey((q.range - predicted) / band) : 0.0;
      }
      weight *= q.spatial;
      if (weight <= 0.0)
        continue;
      // 1/ρ's noise is σ/ρ²: weights in ρ⁴, relative to the centre's.
      const double scale = q.range / r0;
      plane.add(q.x, q.inverse, weight * scale * scale * scale * scale);
      ++supported;
    }
    if (supported < p.min_neighbours + 1 || !plane.solve(w) || !(w(0) > 0.0))
      return have ? 1.0 / w(0) : std::numeric_limits<double>::quiet_NaN();
    have = true;
  }
  return 1.0 / w(0);
}

}  // namespace

void denoiseRangeImage(const RangeImage& image, const RangeNoiseModel& noise, const RangeDenoisingParameters& parameters,
                       std::vector<double>& range_out, RangeDenoisingReport& report)
{
  const auto start = std::chrono::steady_clock::now();
  if (!(noise.coefficient > 0.0) && !(noise.quantum > 0.0))
    throw Error("range denoising needs a noise law (none could be estimated from this frame)");
  const RangeDenoisingParameters& p = parameters;
  if (p.column_radius < 0 || p.beam_radius < 0 || p.column_radius > 64 || p.beam_radius > 16 ||
      !(p.range_sigmas > 0.0) || !(p.spatial_sigma > 0.0) || p.refinements < 0 || p.min_neighbours < 3)
    throw Error("range denoising parameters out of range");
  const std::size_t n = image.width * image.height;
  // Separable Gaussian spatial weights over the window.
  std::vector<double> spatial;
  for (int db = -p.beam_radius; db <= p.beam_radius; ++db)
    for (int dc = -p.column_radius; dc <= p.column_radius; ++dc) {
      const double sb = p.spatial_sigma * std::max(1, p.beam_radius), sc = p.spatial_sigma * std::max(1, p.column_radius);
      spatial.push_back(std::exp(-0.5 * (db * db / (sb * sb) + dc * dc / (sc * sc))));
    }
  const std::vector<double> nearest = nearestMeasuredRange(image);
  const OriginFreeSpace from_origin(image);
  range_out.assign(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> state(n, 0);  // 0 kept, 1 moved, 2 clamped to σ, 3 clamped at free space
  const long long rows = static_cast<long long>(image.height);
  const int threads = p.num_threads > 0 ? p.num_threads : omp_get_max_threads();
#pragma omp parallel num_threads(threads)
  {
    std::vector<Neighbour> window;
#pragma omp for schedule(static)
    for (long long b = 0; b < rows; ++b)
      for (std::size_t c = 0; c < image.width; ++c) {
        const std::size_t i = std::size_t(b) * image.width + c;
        if (!image.valid[i])
          continue;
        const double r0 = image.range[i], sigma = noise.sigma(r0);
        double r = denoisePixel(image, p, spatial, sigma, i, window);
        range_out[i] = r0;
        if (!std::isfinite(r) || !(r > 0.0))
          continue;
        char how = 1;
        const double limit = p.max_shift_sigmas * sigma;
        if (p.max_shift_sigmas > 0.0 && std::abs(r - r0) > limit) {
          r = r0 + std::copysign(limit, r - r0);
          how = 2;
        }
        if (r < r0 && std::isfinite(nearest[i]) && r < nearest[i]) {
          r = std::max(std::min(r0, nearest[i]), r);
          how = 3;
        }
        // Seen from the origin, a point that already lies where the beams crossed (near the sensor,
        // where the beam origins' offset matters) stays as measured; none is moved there.
        if ((r < r0 || from_origin.violates(image.model.pointAt(std::size_t(b), c, r0), i)) &&
            from_origin.violates(image.model.pointAt(std::size_t(b), c, r), i)) {
          r = r0;
          how = 3;
        }
        range_out[i] = r;
        state[i] = r != r0 ? how : 0;
      }
  }
  report = RangeDenoisingReport{};
  double squares = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!image.valid[i])
      continue;
    ++report.measured;
    if (state[i] == 0) {
      ++report.left;
      continue;
    }
    ++report.moved;
    report.clamped += state[i] == 2 ? 1 : 0;
    report.free_space_clamped += state[i] == 3 ? 1 : 0;
    const double shift = (range_out[i] - image.range[i]) / noise.sigma(image.range[i]);
    squares += shift * shift;
  }
  report.rms_shift_sigmas = report.moved ? std::sqrt(squares / double(report.moved)) : 0.0;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace patchdict
}  // namespace pcl
