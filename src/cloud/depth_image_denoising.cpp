// Image-space denoising of depth images (see depth_image_denoising.h): robust local planes in 1/z
// over the pixel grid, one per pixel, with a Gaussian spatial and a Tukey range kernel.
#include <pcl_patchdict/cloud/depth_image_denoising.h>
#include <pcl_patchdict/core/error.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

// y = a + b·du + c·dv: a neighbour's depth offset from the centre pixel, linearised at its depth.
struct Plane {
  double a = 0.0, b = 0.0, c = 0.0;
};

// The weights of one window radius: Gaussian of the distance, and the distance, per offset.
struct Kernel {
  int radius = 0;
  std::vector<double> spatial, distance;  // (2R+1)², row-major over (dv, du)
};

struct Frame {
  const DepthImage* image = nullptr;
  std::vector<double> inverse;  // 1/z, NaN where not measured
  int width = 0, height = 0;
};

// Weighted least squares of the plane over the window of radius kernel.radius around (u, v). A
// neighbour's residual r off `reference` gets the weight spatial × (1 − (r/t)²)², t = t0 + t1·distance,
// zero beyond. False when fewer than min_neighbours have weight or the plane is degenerate.
bool fitPlane(const Frame& frame, int u, int v, const Kernel& kernel, int stride, const Plane& reference, double t0,
              double t1, int min_neighbours, Plane& out)
{
  const int R = kernel.radius, side = 2 * R + 1;
  const std::size_t centre = static_cast<std::size_t>(v) * frame.width + u;
  const double wp = frame.inverse[centre], zp = 1.0 / wp, zp2 = zp * zp;
  double S = 0, Su = 0, Sv = 0, Suu = 0, Suv = 0, Svv = 0, Sy = 0, Suy = 0, Svy = 0;
  int count = 0;
  // The window's rows and columns at multiples of `stride` from the centre, inside the image.
  const int reach = R / stride * stride;
  const int v0 = v - std::min(reach, v / stride * stride), v1 = v + std::min(reach, (frame.height - 1 - v) / stride * stride);
  const int u0 = u - std::min(reach, u / stride * stride), u1 = u + std::min(reach, (frame.width - 1 - u) / stride * stride);
  for (int q = v0; q <= v1; q += stride) {
    const int dv = q - v;
    const double* row = frame.inverse.data() + static_cast<std::size_t>(q) * frame.width;
    const std::size_t k0 = static_cast<std::size_t>(dv + R) * side + R;
    for (int p = u0; p <= u1; p += stride) {
      const double wq = row[p];
      if (!(wq == wq))
        continue;
      const int du = p - u;
      const std::size_t k = k0 + du;
      const double y = (wp - wq) * zp2;
      const double r = y - (reference.a + reference.b * du + reference.c * dv);
      const double t = t0 + t1 * kernel.distance[k];
      const double s = r / t;
      if (!(s * s < 1.0))
        continue;
      const double tukey = (1.0 - s * s) * (1.0 - s * s);
      const double w = kernel.spatial[k] * tukey;
      const double wu = w * du, wv = w * dv;
      S += w;
      Su += wu;
      Sv += wv;
      Suu += wu * du;
      Suv += wu * dv;
      Svv += wv * dv;
      Sy += w * y;
      Suy += wu * y;
      Svy += wv * y;
      ++count;
    }
  }
  if (count < min_neighbours || !(S > 0.0))
    return false;
  // Centre the moments on the weighted mean offset, solve the 2 × 2 slope system, then the intercept.
  const double mu = Su / S, mv = Sv / S, my = Sy / S;
  const double cuu = Suu - Su * mu, cuv = Suv - Su * mv, cvv = Svv - Sv * mv;
  const double cuy = Suy - Su * my, cvy = Svy - Sv * my;
  const double det = cuu * cvv - cuv * cuv;
  // Degenerate: the weighted neighbours lie (nearly) on a line; their spread across it would be
  // below a tenth of a pixel.
  if (!(det > 0.01 * S * std::max(cuu, cvv)))
    return false;
  out.b = (cvv * cuy - cuv * cvy) / det;
  out.c = (cuu * cvy - cuv * cuy) / det;
  out.a = my - out.b * mu - out.c * mv;
  return std::isfinite(out.a) && std::isfinite(out.b) && std::isfinite(out.c);
}

Kernel makeKernel(int radius, double spatial_sigma)
{
  Kernel kernel;
  kernel.radius = radius;
  const int side = 2 * radius + 1;
  const double sigma = std::max(0.5, spatial_sigma * radius);
  kernel.spatial.resize(static_cast<std::size_t>(side) * side);
  kernel.distance.resize(kernel.spatial.size());
  for (int dv = -radius; dv <= radius; ++dv)
    for (int du = -radius; du <= radius; ++du) {
      const std::size_t k = static_cast<std::size_t>(dv + radius) * side + (du + radius);
      const double d2 = static_cast<double>(du * du + dv * dv);
      kernel.distance[k] = std::sqrt(d2);
      kernel.spatial[k] = std::exp(-0.5 * d2 / (sigma * sigma));
    }
  return kernel;
}

}  // namespace

int depthDenoisingRadius(const PinholeCamera& camera, const DepthDenoisingParameters& parameters, double z)
{
  const int low = std::max(1, parameters.min_radius), high = std::max(low, parameters.max_radius);
  if (!(z > 0.0) || !camera.valid)
    return low;
  const double metres = parameters.window_radius *
                        std::pow(z / std::max(1e-12, parameters.reference_depth), parameters.window_exponent);
  const double pixels = metres / camera.pixelSpacing(z);
  if (!std::isfinite(pixels))
    return low;
  return static_cast<int>(std::clamp(std::lround(pixels), static_cast<long>(low), static_cast<long>(high)));
}

namespace {

/// The 5th and 95th percentiles of the measured depths, and the window radii there.
void depthRange(const DepthImage& image, const DepthDenoisingParameters& parameters, std::vector<double> sorted,
                DepthDenoisingReport& report)
{
  const auto at = [&](std::size_t k) {
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
    return sorted[k];
  };
  report.depth_near = at(sorted.size() / 20);
  report.depth_far = at(sorted.size() - 1 - sorted.size() / 20);
  report.radius_near = depthDenoisingRadius(image.camera, parameters, report.depth_near);
  report.radius_far = depthDenoisingRadius(image.camera, parameters, report.depth_far);
}

/// What every pixel's fit reads: the frame, the noise, the kernels per radius and the settings.
struct PixelFilter {
  const Frame& frame;
  const DepthNoiseModel& noise;
  const DepthDenoisingParameters& parameters;
  std::vector<Kernel> kernels;  // per window radius
  Kernel seed_kernel;
  double range = 0.0, pixel_scale = 0.0;
  int min_neighbours = 0, stride = 0;
};

/// One pixel's outcome: its depth, the window radius it used, whether its shift was clamped.
struct PixelResult {
  enum class Outcome { Moved, Left } outcome = Outcome::Left;
  double depth = 0.0;
  int radius = 0;
  bool clamped = false;
};

/// The pixel i = (u, v), measured (1/z finite), onto its robust local plane.
PixelResult denoisePixel(const PixelFilter& f, int u, int v, std::size_t i)
{
  const DepthImage& image = *f.frame.image;
  const DepthDenoisingParameters& parameters = f.parameters;
  PixelResult result;
  const double wp = f.frame.inverse[i];
  const double z = image.depth[i], sigma = f.noise.sigma(z);
  result.depth = z;
  const double t = f.range * sigma;
  // Seed plane: about the pixel's own depth with the slope allowance, then about itself.
  Plane plane;
  const double allowance = parameters.slope_allowance * z * f.pixel_scale;
  if (!fitPlane(f.frame, u, v, f.seed_kernel, 1, Plane(), t, allowance, 3, plane) ||
      !fitPlane(f.frame, u, v, f.seed_kernel, 1, Plane(plane), t, 0.0, 3, plane)) {
    // Too little support around the pixel for a seed plane: a flat reference at its own depth.
    plane = Plane();
  }
  const int R = depthDenoisingRadius(image.camera, parameters, z);
  result.radius = R;
  const Kernel& kernel = f.kernels[R];
  bool ok = fitPlane(f.frame, u, v, kernel, f.stride, Plane(plane), t, 0.0, f.min_neighbours, plane);
  for (int k = 0; ok && k < parameters.refinements; ++k)
    ok = fitPlane(f.frame, u, v, kernel, f.stride, Plane(plane), t, 0.0, f.min_neighbours, plane);
  if (!ok)
    return result;
  double shift = plane.a;  // depth offset at the centre, linearised
  const double limit = parameters.max_shift_sigmas * sigma;
  if (parameters.max_shift_sigmas > 0.0 && std::abs(shift) > limit) {
    shift = std::copysign(limit, shift);
    result.clamped = true;
  }
  // y = (1/z_p − 1/z)·z_p²  ⇒  1/z = 1/z_p − y/z_p².
  const double out = 1.0 / (wp - shift * wp * wp);
  if (!(out > 0.0) || !std::isfinite(out))
    return result;
  result.depth = out;
  result.outcome = PixelResult::Outcome::Moved;
  return result;
}

}  // namespace

void denoiseDepthImage(const DepthImage& image, const DepthNoiseModel& noise, const DepthDenoisingParameters& parameters,
                       std::vector<double>& depth_out, DepthDenoisingReport& report)
{
  const auto start = std::chrono::steady_clock::now();
  report = DepthDenoisingReport();
  if (!image.camera.valid)
    throw Error("denoiseDepthImage: the image has no valid pinhole camera");
  if (!(noise.coefficient > 0.0) || !std::isfinite(noise.coefficient))
    throw Error("denoiseDepthImage: the depth noise model has no coefficient");
  const std::size_t n = image.width * image.height;
  if (image.depth.size() != n || image.valid.size() != n)
    throw Error("denoiseDepthImage: the depth image's buffers do not match its size");

  Frame frame;
  frame.image = &image;
  frame.width = static_cast<int>(image.width);
  frame.height = static_cast<int>(image.height);
  frame.inverse.assign(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<double> depths;
  for (std::size_t i = 0; i < n; ++i)
    if (image.valid[i] && image.depth[i] > 0.0 && std::isfinite(image.depth[i])) {
      frame.inverse[i] = 1.0 / image.depth[i];
      depths.push_back(image.depth[i]);
    }
  report.measured = depths.size();
  depth_out.assign(n, std::numeric_limits<double>::quiet_NaN());
  if (depths.empty()) {
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return;
  }
  depthRange(image, parameters, depths, report);

  const int low = std::max(1, parameters.min_radius), high = std::max(low, parameters.max_radius);
  PixelFilter filter{frame, noise, parameters, std::vector<Kernel>(static_cast<std::size_t>(high) + 1), Kernel(), 0.0, 0.0, 0, 0};
  for (int r = low; r <= high; ++r)
    filter.kernels[r] = makeKernel(r, parameters.spatial_sigma);
  const int seed = std::max(1, parameters.seed_radius);
  filter.seed_kernel = makeKernel(seed, parameters.spatial_sigma);
  filter.range = std::max(1e-6, parameters.range_sigmas);
  filter.min_neighbours = std::max(3, parameters.min_neighbours);
  filter.stride = std::max(1, parameters.window_stride);
  filter.pixel_scale = 1.0 / std::sqrt(image.camera.fx * image.camera.fy);  // pixel spacing / z

  int threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();
  std::size_t moved = 0, left = 0, clamped = 0;
  // The squared shifts are summed per row and the rows added in order afterwards: an OpenMP
  // reduction would add them in the order the threads finish, and the report's last bits would
  // depend on the thread count.
  std::vector<double> row_shift2(static_cast<std::size_t>(frame.height), 0.0);
  int radius_min = high, radius_max = low;
#pragma omp parallel for schedule(dynamic, 2) num_threads(threads) reduction(+ : moved, left, clamped) \
    reduction(min : radius_min) reduction(max : radius_max)
  for (int v = 0; v < frame.height; ++v)
    for (int u = 0; u < frame.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * frame.width + u;
      const double wp = frame.inverse[i];
      if (!(wp == wp))
        continue;
      const PixelResult result = denoisePixel(filter, u, v, i);
      const double z = image.depth[i], sigma = noise.sigma(z);
      depth_out[i] = result.depth;
      radius_min = std::min(radius_min, result.radius);
      radius_max = std::max(radius_max, result.radius);
      clamped += result.clamped ? 1 : 0;
      if (result.outcome == PixelResult::Outcome::Left) {
        ++left;
        continue;
      }
      const double out = result.depth;
      if (out != z) {
        ++moved;
        row_shift2[static_cast<std::size_t>(v)] += ((out - z) / sigma) * ((out - z) / sigma);
      }
    }
  double shift2 = 0.0;
  for (const double row : row_shift2)
    shift2 += row;
  report.moved = moved;
  report.left = left;
  report.clamped = clamped;
  report.rms_shift_sigmas = moved ? std::sqrt(shift2 / static_cast<double>(moved)) : 0.0;
  report.radius_min = std::min(radius_min, radius_max);
  report.radius_max = radius_max;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace patchdict
}  // namespace pcl
