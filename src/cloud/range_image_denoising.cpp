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

// A pixel's window, structure of arrays: the loops over it have no branches.
struct Window {
  std::vector<double> x0, x1, x2, inverse, range, spatial, distance, weight;
  std::size_t size = 0;
  void reserve(std::size_t n)
  {
    for (auto* v : {&x0, &x1, &x2, &inverse, &range, &spatial, &distance, &weight})
      v->resize(n);
  }
};

// Tukey's biweight (1 − r²)² for |r| < 1, else 0, without a branch.
inline double tukey(double r)
{
  const double t = 1.0 - std::min(r * r, 1.0);
  return t * t;
}

// The basis coordinates (u·u_c, u·e1/s, u·e2/s) of every window offset (db, dc) about a pixel of
// beam b, e1 = u_c × z: a turn about the spin axis carries them along, so they depend on the beams
// and the column offset only, not on the column. Indexed [b][db + B][dc + R].
std::vector<Eigen::Vector3d> windowCoordinates(const SpinningSensorModel& m, int R, int B)
{
  const std::size_t H = m.height, span = std::size_t(2 * B + 1) * std::size_t(2 * R + 1);
  const double step = std::abs(m.azimuth_step);
  std::vector<Eigen::Vector3d> table(H * span, Eigen::Vector3d::Zero());
  for (std::size_t b = 0; b < H; ++b) {
    const Eigen::Vector3d u = m.direction(b, 0.0);
    const detail::RayBasis basis(u, step);
    for (int db = -B; db <= B; ++db) {
      if ((db < 0 && b < std::size_t(-db)) || b + db >= H)
        continue;
      for (int dc = -R; dc <= R; ++dc)
        table[b * span + std::size_t((db + B) * (2 * R + 1) + dc + R)] =
            basis.coordinates(m.direction(b + db, static_cast<double>(dc)));
    }
  }
  return table;
}

// The new range of pixel i, or NaN when it keeps its own (too few neighbours, degenerate plane).
double denoisePixel(const RangeImage& image, const RangeDenoisingParameters& p, const std::vector<double>& spatial,
                    const std::vector<double>& distance, const std::vector<Eigen::Vector3d>& coordinates,
                    const std::vector<double>& inverse, double sigma, std::size_t i, Window& window)
{
  const std::size_t W = image.width, H = image.height;
  const std::size_t b = i / W, c = i % W;
  const double r0 = image.range[i], step = std::abs(image.model.azimuth_step);
  const int R = p.column_radius, B = p.beam_radius;
  const std::size_t span = std::size_t(2 * B + 1) * std::size_t(2 * R + 1);
  std::size_t n = 0;
  const long long columns = static_cast<long long>(W);
  for (int db = -B; db <= B; ++db) {
    if ((db < 0 && b < std::size_t(-db)) || b + db >= H)
      continue;
    for (int dc = -R; dc <= R; ++dc) {
      long long cc = static_cast<long long>(c) + dc;  // the azimuth wraps (no division here: it is hot)
      if (cc < 0 || cc >= columns) {
        if (!image.model.wraps)
          continue;
        cc += cc < 0 ? columns : -columns;
      }
      const std::size_t j = (b + db) * W + static_cast<std::size_t>(cc);
      if (!image.valid[j])
        continue;
      const std::size_t k = std::size_t((db + B) * (2 * R + 1) + (dc + R));
      const Eigen::Vector3d& x = coordinates[b * span + k];
      window.x0[n] = x(0);
      window.x1[n] = x(1);
      window.x2[n] = x(2);
      window.range[n] = image.range[j];
      window.inverse[n] = inverse[j];
      window.spatial[n] = spatial[k];
      window.distance[n] = distance[k];
      ++n;
    }
  }
  // 1/ρ's noise is σ/ρ²: weights in ρ⁴, relative to the centre's (folded into the spatial weight).
  const double inverse_r0 = 1.0 / r0;
  for (std::size_t q = 0; q < n; ++q) {
    const double scale = window.range[q] * inverse_r0;
    window.spatial[q] *= scale * scale * scale * scale;
  }
  const double band = p.range_sigmas * sigma, inverse_band = 1.0 / band;
  const double slope = p.slope_allowance * r0 * step;
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  bool have = false;
  for (int pass = 0; pass <= p.refinements; ++pass) {
    if (pass == 0)
      for (std::size_t q = 0; q < n; ++q)
        window.weight[q] = window.spatial[q] * tukey((window.range[q] - r0) / (band + slope * window.distance[q]));
    else
      for (std::size_t q = 0; q < n; ++q) {
        // The range's misfit to first order in 1/ρ's, ρ − 1/(w·x) ≈ ρ²·(w·x − 1/ρ): exact enough
        // where the weight is not 0 (|misfit| ≪ ρ), and no division.
        const double plane_inverse = w(0) * window.x0[q] + w(1) * window.x1[q] + w(2) * window.x2[q];
        const double misfit = window.range[q] * window.range[q] * (plane_inverse - window.inverse[q]);
        window.weight[q] = window.spatial[q] * tukey(misfit * inverse_band);
      }
    detail::InverseRangePlane plane;
    int supported = 0;
    for (std::size_t q = 0; q < n; ++q) {
      const double v = window.weight[q];
      const double wx0 = v * window.x0[q], wx1 = v * window.x1[q], wx2 = v * window.x2[q];
      plane.a00 += wx0 * window.x0[q];
      plane.a01 += wx0 * window.x1[q];
      plane.a02 += wx0 * window.x2[q];
      plane.a11 += wx1 * window.x1[q];
      plane.a12 += wx1 * window.x2[q];
      plane.a22 += wx2 * window.x2[q];
      plane.b0 += wx0 * window.inverse[q];
      plane.b1 += wx1 * window.inverse[q];
      plane.b2 += wx2 * window.inverse[q];
      supported += v > 0.0 ? 1 : 0;
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
      !(p.range_sigmas > 0.0) || !(p.spatial_sigma > 0.0) || p.refinements < 0 || p.min_neighbours < 3 ||
      !(p.free_space_spacing >= 0.0) || !(p.free_space_relative >= 0.0))
    throw Error("range denoising parameters out of range");
  const std::size_t n = image.width * image.height;
  // Separable Gaussian spatial weights over the window.
  std::vector<double> spatial, distance;
  for (int db = -p.beam_radius; db <= p.beam_radius; ++db)
    for (int dc = -p.column_radius; dc <= p.column_radius; ++dc) {
      distance.push_back(std::sqrt(double(db * db + dc * dc)));
      const double sb = p.spatial_sigma * std::max(1, p.beam_radius), sc = p.spatial_sigma * std::max(1, p.column_radius);
      spatial.push_back(std::exp(-0.5 * (db * db / (sb * sb) + dc * dc / (sc * sc))));
    }
  const std::vector<Eigen::Vector3d> coordinates = windowCoordinates(image.model, p.column_radius, p.beam_radius);
  const std::vector<double> nearest = nearestMeasuredRange(image);
  std::vector<double> inverse(n, 0.0);  // 1/ρ per pixel, once
  for (std::size_t i = 0; i < n; ++i)
    inverse[i] = image.valid[i] ? 1.0 / image.range[i] : 0.0;
  const OriginFreeSpace from_origin(image, p.free_space_spacing, p.free_space_relative);
  range_out.assign(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> state(n, 0);  // 0 kept, 1 moved, 2 clamped to σ, 3 clamped at free space
  std::vector<double> sigmas(n, 0.0);
  const long long rows = static_cast<long long>(image.height);
  const int threads = p.num_threads > 0 ? p.num_threads : omp_get_max_threads();
#pragma omp parallel num_threads(threads)
  {
    Window window;
    window.reserve(spatial.size());
#pragma omp for schedule(dynamic, 1)
    for (long long b = 0; b < rows; ++b)
      for (std::size_t c = 0; c < image.width; ++c) {
        const std::size_t i = std::size_t(b) * image.width + c;
        if (!image.valid[i])
          continue;
        const double r0 = image.range[i], sigma = noise.sigma(r0);
        sigmas[i] = sigma;
        double r = denoisePixel(image, p, spatial, distance, coordinates, inverse, sigma, i, window);
        range_out[i] = r0;
        if (!std::isfinite(r) || !(r > 0.0))
          continue;
        char how = 1;
        const double limit = p.max_shift_sigmas * sigma;
        if (p.max_shift_sigmas > 0.0 && std::abs(r - r0) > limit) {
          r = r0 + std::copysign(limit, r - r0);
          how = 2;
        }
        const double least = freeSpaceBound(nearest[i], image.model.azimuth_step, p.free_space_spacing,
                                            p.free_space_relative);
        if (r < r0 && r < least) {
          r = std::min(r0, least);
          how = 3;
        }
        // Seen from the origin, a point that already lies where the beams crossed (near the sensor,
        // where the beam origins' offset matters) stays as measured; none is moved there.
        if (r != r0 && (r < r0 || from_origin.violates(image.pointAt(i, r0), i)) &&
            from_origin.violates(image.pointAt(i, r), i)) {
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
    const double shift = (range_out[i] - image.range[i]) / sigmas[i];
    squares += shift * shift;
  }
  report.rms_shift_sigmas = report.moved ? std::sqrt(squares / double(report.moved)) : 0.0;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace patchdict
}  // namespace pcl
