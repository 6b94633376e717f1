// Image-space denoising of depth images (see depth_image_denoising.h): robust local planes in 1/z
// over the pixel grid, one per pixel, with a Gaussian spatial and a Tukey range kernel.
//
// Speed. The pixels of a row are fitted 16 at a time with AVX-512, else 8, one per lane of GCC's
// generic vectors: for each sample offset of the window, the lanes read the neighbours of
// consecutive pixels, which are consecutive floats of 1/z. Each lane sums its own
// pixel's samples in the window's order and solves its own plane (in double), so no lane ever meets
// another: the AVX-512, AVX2 and portable builds give the same bits, and so does any thread count.
// Each lane's radius picks its spatial weights from a per-offset table (0 beyond its window). No
// FMA: contracting a·b + c would change the bits between the builds. Float is ample: a neighbour's
// offset wp − wq is exact for nearby depths, and rounding 1/z to float moves a depth by 6e-8 of
// itself, against noise of 1e-3 of it.
#include "coding/correlations.h"  // activeSimdKernels: which build of the row loop the CPU runs

#include <pcl_patchdict/cloud/depth_image_denoising.h>
#include <pcl_patchdict/core/error.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#pragma GCC optimize("fp-contract=off")

namespace pcl {
namespace patchdict {

namespace {

typedef float F8 __attribute__((vector_size(32)));
typedef int I8 __attribute__((vector_size(32)));
typedef float F16 __attribute__((vector_size(64)));
typedef int I16 __attribute__((vector_size(64)));

template <class V> struct LanesOf;
template <> struct LanesOf<F8> {
  using Int = I8;
  static constexpr int size = 8;
};
template <> struct LanesOf<F16> {
  using Int = I16;
  static constexpr int size = 16;
};

#define PD_INLINE inline __attribute__((always_inline))

/// The most window samples either side of a pixel (max_radius / window_stride, and seed_radius).
constexpr int kMaxWindowReach = 32;

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

// 1/z as floats, NaN where not measured, in rows of `pitch` whose NaN margins let a window read past
// the image's sides.
struct Grid {
  int margin = 0, pitch = 0, height = 0;
  std::vector<float> data;
  const float* row(int r) const { return data.data() + static_cast<std::size_t>(r) * pitch + margin; }
};

Grid makeGrid(const std::vector<float>& inverse, int width, int height, int reach)
{
  Grid grid;
  grid.height = height;
  grid.margin = reach + 16;  // a window's reach, and 16 lanes to the right
  grid.pitch = width + 2 * grid.margin;
  grid.data.assign(static_cast<std::size_t>(height) * grid.pitch, std::numeric_limits<float>::quiet_NaN());
#pragma omp parallel for schedule(static)
  for (int r = 0; r < height; ++r)
    std::copy_n(inverse.data() + static_cast<std::size_t>(r) * width, width,
                grid.data.data() + static_cast<std::size_t>(r) * grid.pitch + grid.margin);
  return grid;
}

typedef double D8 __attribute__((vector_size(64)));
typedef long long L8 __attribute__((vector_size(64)));

// (Vectors go by reference: by value they would change the ABI between the builds.)
template <class V> PD_INLINE void load(V& x, const float* p) { std::memcpy(&x, p, sizeof x); }

// Lanes 8k … 8k + 7 of a float vector as doubles, and back.
template <class V> PD_INLINE void widen(const V& x, int k, D8& out)
{
  if constexpr (LanesOf<V>::size == 16)
    out = k == 0 ? __builtin_convertvector(__builtin_shufflevector(x, x, 0, 1, 2, 3, 4, 5, 6, 7), D8)
                 : __builtin_convertvector(__builtin_shufflevector(x, x, 8, 9, 10, 11, 12, 13, 14, 15), D8);
  else
    out = __builtin_convertvector(x, D8);
}
template <class V> PD_INLINE void narrow(const D8* x, V& out)
{
  if constexpr (LanesOf<V>::size == 16) {
    const F8 low = __builtin_convertvector(x[0], F8), high = __builtin_convertvector(x[1], F8);
    out = __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  } else {
    out = __builtin_convertvector(x[0], F8);
  }
}

// The settings every row reads: the grid, the seed window's weights, the full windows' weights per
// offset and radius, the noise, the parameters.
struct LaneFilter {
  const DepthImage& image;
  const DepthNoiseModel& noise;
  const DepthDenoisingParameters& parameters;
  Grid grid;
  int stride = 1, low = 1, high = 1, seed_reach = 2, reach = 0, table_size = 16, min_neighbours = 6;
  std::vector<float> seed_spatial, seed_distance;  // per seed offset, (2·seed_reach + 1)² row-major
  std::vector<float> table;  // per full offset ((2·reach + 1)² row-major) table_size weights by R − low
  double range = 0.0, pixel_scale = 0.0;
};

void prepareLaneFilter(LaneFilter& f, const std::vector<float>& inverse)
{
  const DepthDenoisingParameters& parameters = f.parameters;
  f.low = std::max(1, parameters.min_radius);
  f.high = std::max(f.low, parameters.max_radius);
  f.stride = std::max(1, parameters.window_stride);
  f.seed_reach = std::max(1, parameters.seed_radius);
  f.reach = f.high / f.stride;
  f.table_size = (f.high - f.low + 16) / 16 * 16;
  f.range = std::max(1e-6, parameters.range_sigmas);
  f.min_neighbours = std::max(3, parameters.min_neighbours);
  f.pixel_scale = 1.0 / std::sqrt(f.image.camera.fx * f.image.camera.fy);  // pixel spacing / z
  const auto gauss = [&](int radius, int du, int dv) {
    const double sigma = std::max(0.5, parameters.spatial_sigma * radius);
    return static_cast<float>(std::exp(-0.5 * static_cast<double>(du * du + dv * dv) / (sigma * sigma)));
  };
  const int S = f.seed_reach;
  for (int dv = -S; dv <= S; ++dv)
    for (int du = -S; du <= S; ++du) {
      f.seed_spatial.push_back(gauss(S, du, dv));
      f.seed_distance.push_back(static_cast<float>(std::sqrt(static_cast<double>(du * du + dv * dv))));
    }
  for (int jv = -f.reach; jv <= f.reach; ++jv)
    for (int ju = -f.reach; ju <= f.reach; ++ju)
      for (int k = 0; k < f.table_size; ++k) {
        const int R = f.low + k;  // its window: multiples of stride up to R / stride · stride
        const bool inside = R <= f.high && std::max(std::abs(ju), std::abs(jv)) <= R / f.stride;
        f.table.push_back(inside ? gauss(R, ju * f.stride, jv * f.stride) : 0.0f);
      }
  f.grid = makeGrid(inverse, static_cast<int>(f.image.width), static_cast<int>(f.image.height),
                    std::max(f.high, f.seed_reach));
}

// The pixels u0 … u0 + lanes − 1 of row v: 1/z, and per lane z², the Tukey scale z²/t (t = range·σ(z)),
// t and the slope allowance (for the first seed fit), the radius's table index.
template <class V> struct Block {
  using Int = typename LanesOf<V>::Int;
  int u0 = 0, v = 0, reach = 0;
  V wp, g, scale, t, allowance;
  Int radius;
};

// A plane per lane, a + b·du + c·dv in 1/z units, in double, and whether its fit held.
struct LanePlanes {
  D8 a[2], b[2], c[2];
  L8 ok[2];
};

// The sums of one fit per lane (see the header): S, Su, Sv, Suu, Suv, Svv, Sd, Sud, Svd and the
// count. A neighbour's residual r off the lane's `reference` gets the weight
// spatial × (1 − (r/t)²)², t = t0 + t1·distance (t1: the first seed fit only), zero beyond.
template <class V>
PD_INLINE void laneSums(const LaneFilter& f, const Block<V>& b, bool full, bool allowance, const LanePlanes& ref,
                        V sums[10])
{
  using Int = typename LanesOf<V>::Int;
  const V zero = V{}, one = zero + 1.0f;
  V ra, rb, rc;
  narrow(ref.a, ra), narrow(ref.b, rb), narrow(ref.c, rc);
  const int s = full ? f.stride : 1, J = full ? b.reach : f.seed_reach;
  const int table_reach = full ? f.reach : f.seed_reach, table_side = 2 * table_reach + 1;
  for (int k = 0; k < 10; ++k)
    sums[k] = zero;
  // Per window column: the plane's slope term rb·du, du and du² (the same products in every row of the
  // window, computed once).
  constexpr int max_side = 2 * kMaxWindowReach + 1;
  V slope[max_side], column[max_side], column2[max_side];
  for (int ju = -J; ju <= J; ++ju) {
    const float du = static_cast<float>(ju * s);
    slope[ju + J] = rb * du, column[ju + J] = zero + du, column2[ju + J] = zero + du * du;
  }
  for (int jv = -J; jv <= J; ++jv) {
    const int dv = jv * s;
    if (b.v + dv < 0 || b.v + dv >= f.grid.height)
      continue;
    const float* source = f.grid.row(b.v + dv) + b.u0;
    const float fv = static_cast<float>(dv);
    const V base = b.wp - (ra + rc * fv);
    V rS = zero, rSu = zero, rSuu = zero, rSd = zero, rSud = zero, rN = zero;
    // The full window's weights per offset: row jv of the table, from its column −J (seed fits read
    // their own small table instead, by offset).
    std::size_t entry = full ? (static_cast<std::size_t>(jv + table_reach) * table_side + (table_reach - J)) * f.table_size : 0;
    for (int ju = -J; ju <= J; ++ju, entry += full ? f.table_size : 0) {
      const std::size_t offset = static_cast<std::size_t>(jv + table_reach) * table_side + (ju + table_reach);
      V weight, inv = b.scale, q;
      if (full) {
        if (f.table_size == 16) {
          F16 all;
          load(all, f.table.data() + entry);
          if constexpr (LanesOf<V>::size == 16)
            weight = __builtin_shuffle(all, b.radius);
          else
            weight = __builtin_shuffle(__builtin_shufflevector(all, all, 0, 1, 2, 3, 4, 5, 6, 7),
                                       __builtin_shufflevector(all, all, 8, 9, 10, 11, 12, 13, 14, 15), b.radius);
        } else {
          for (int l = 0; l < LanesOf<V>::size; ++l)
            weight[l] = f.table[entry + static_cast<std::size_t>(b.radius[l])];
        }
      } else {
        weight = zero + f.seed_spatial[offset];
        if (allowance)
          inv = b.g / (b.t + b.allowance * f.seed_distance[offset]);
      }
      load(q, source + ju * s);
      const V r = (base - slope[ju + J] - q) * inv;
      const V r2 = r * r;
      const Int inside = r2 < one;  // false for NaN: no measurement
      const V tukey = one - r2;
      // Selects rather than masks, so that each is one masked instruction.
      const V w = inside ? weight * (tukey * tukey) : zero;
      const V wd = w * (inside ? b.wp - q : zero);
      rS += w;
      rSu += w * column[ju + J];
      rSuu += w * column2[ju + J];
      rSd += wd;
      rSud += wd * column[ju + J];
      rN = w > zero ? rN + one : rN;
    }
    sums[9] += rN;
    sums[0] += rS, sums[1] += rSu, sums[2] += fv * rS, sums[3] += rSuu, sums[4] += fv * rSu;
    sums[5] += (fv * fv) * rS, sums[6] += rSd, sums[7] += rSud, sums[8] += fv * rSd;
  }
}

// Weighted least squares of each lane's plane from its sums: the 2 × 2 slope system of the moments
// centred on the weighted mean, each scaled by S (so that one division solves it), then the
// intercept. A lane fails with fewer than min_count samples of weight, a degenerate window (the
// weighted neighbours (nearly) on a line: their spread across it below a tenth of a pixel) or a
// plane that is not finite.
template <class V>
PD_INLINE void solveLanes(const V sums[10], double min_count, LanePlanes& out)
{
  for (int k = 0; k < LanesOf<V>::size / 8; ++k) {
    D8 m[10];
    for (int j = 0; j < 10; ++j)
      widen(sums[j], k, m[j]);
    const D8 &S = m[0], &Su = m[1], &Sv = m[2], &Suu = m[3], &Suv = m[4], &Svv = m[5], &Sd = m[6], &Sud = m[7];
    const D8 &Svd = m[8], &count = m[9];
    const D8 Cuu = S * Suu - Su * Su, Cuv = S * Suv - Su * Sv, Cvv = S * Svv - Sv * Sv;
    const D8 Cuy = S * Sud - Su * Sd, Cvy = S * Svd - Sv * Sd;
    const D8 det = Cuu * Cvv - Cuv * Cuv, larger = Cuu < Cvv ? Cvv : Cuu;
    const D8 inverse_det = 1.0 / det, inverse_S = 1.0 / S;
    const D8 b = (Cvv * Cuy - Cuv * Cvy) * inverse_det, c = (Cuu * Cvy - Cuv * Cuy) * inverse_det;
    const D8 a = (Sd - b * Su - c * Sv) * inverse_S;
    out.a[k] = a, out.b[k] = b, out.c[k] = c;
    out.ok[k] = (count > min_count - 0.5) & (S > 0.0) & (det > 0.01 * S * S * larger) & (a - a == 0.0) &
                (b - b == 0.0) & (c - c == 0.0);
  }
}

// One fit of every lane about `reference`; a lane that failed before stays failed.
template <class V>
PD_INLINE void fitLanes(const LaneFilter& f, const Block<V>& b, bool full, bool allowance, const LanePlanes& reference,
                        LanePlanes& out)
{
  V sums[10];
  laneSums(f, b, full, allowance, reference, sums);
  LanePlanes fitted = reference;
  solveLanes(sums, full ? f.min_neighbours : 3, fitted);
  for (int k = 0; k < LanesOf<V>::size / 8; ++k)
    fitted.ok[k] &= reference.ok[k];
  out = fitted;
}

/// What a row adds to the report.
struct RowTally {
  std::size_t moved = 0, left = 0, clamped = 0;
  double shift2 = 0.0;
  int radius_min = std::numeric_limits<int>::max(), radius_max = 0;
};

/// The new depth of a pixel at depth z from its plane's offset a (1/z units), into `out` and the tally;
/// without a plane it keeps its depth.
void finishPixel(const DepthDenoisingParameters& parameters, double z, double sigma, bool ok, double a, double& out,
                 RowTally& tally)
{
  out = z;
  if (!ok) {
    ++tally.left;
    return;
  }
  double shift = a * z * z;  // depth offset at the centre, linearised
  const double limit = parameters.max_shift_sigmas * sigma;
  if (parameters.max_shift_sigmas > 0.0 && std::abs(shift) > limit) {
    shift = std::copysign(limit, shift);
    ++tally.clamped;
  }
  // y = (1/z_p − 1/z)·z_p²  ⇒  1/z = 1/z_p − y/z_p².
  const double wp = 1.0 / z;
  const double depth = 1.0 / (wp - shift * wp * wp);
  if (!(depth > 0.0) || !std::isfinite(depth)) {
    ++tally.left;
    return;
  }
  out = depth;
  if (depth != z) {
    ++tally.moved;
    tally.shift2 += ((depth - z) / sigma) * ((depth - z) / sigma);
  }
}

// The lanes' planes: the seed plane (about the pixel's own depth with the slope allowance, then
// about itself; a flat reference at its own depth where either fails), then the full window's fits.
template <class V> PD_INLINE void fitBlock(const LaneFilter& f, const Block<V>& b, LanePlanes& plane)
{
  LanePlanes flat;
  for (int k = 0; k < 2; ++k)
    flat.a[k] = flat.b[k] = flat.c[k] = D8{}, flat.ok[k] = L8{} - 1;
  LanePlanes seed;
  fitLanes(f, b, false, true, flat, seed);
  fitLanes(f, b, false, false, seed, seed);
  for (int k = 0; k < LanesOf<V>::size / 8; ++k) {
    seed.a[k] = seed.ok[k] ? seed.a[k] : 0.0, seed.b[k] = seed.ok[k] ? seed.b[k] : 0.0;
    seed.c[k] = seed.ok[k] ? seed.c[k] : 0.0, seed.ok[k] = flat.ok[k];
  }
  plane = seed;
  for (int k = 0; k <= f.parameters.refinements; ++k)
    fitLanes(f, b, true, false, plane, plane);
}

/// σ(z) and the window radius of the depths a thread met last, by their bits: a quantised sensor
/// (a Kinect's 11-bit disparity) has few distinct depths (313 in the shared Kinect frame), so
/// nearly every lookup hits.
struct KnownDepths {
  struct Entry {
    double z = std::numeric_limits<double>::quiet_NaN(), sigma = 0.0;
    int R = 0;
  };
  static constexpr std::uint64_t size = 4096;
  std::vector<Entry> entries = std::vector<Entry>(size);
};

/// Row v of the image, denoised into depth_out, `lanes` pixels at a time.
template <class V>
PD_INLINE void denoiseRowBody(const LaneFilter& f, int v, double* depth_out, RowTally& tally, KnownDepths& known)
{
  constexpr int P = LanesOf<V>::size;
  const DepthImage& image = f.image;
  const int W = static_cast<int>(image.width);
  const DepthDenoisingParameters& parameters = f.parameters;
  double z[P], sigmas[P];
  for (int u0 = 0; u0 < W; u0 += P) {
    Block<V> b;
    b.u0 = u0, b.v = v;
    load(b.wp, f.grid.row(v) + u0);
    b.g = b.scale = b.t = b.allowance = V{};
    b.radius = typename LanesOf<V>::Int{};
    bool any = false;
    for (int l = 0; l < P; ++l) {
      if (!(b.wp[l] == b.wp[l]))
        continue;
      any = true;
      z[l] = image.depth[static_cast<std::size_t>(v) * W + u0 + l];
      std::uint64_t bits;
      std::memcpy(&bits, &z[l], sizeof bits);
      KnownDepths::Entry& entry = known.entries[(bits ^ (bits >> 29) ^ (bits >> 41)) & (KnownDepths::size - 1)];
      if (!(entry.z == z[l])) {
        entry.z = z[l];
        entry.sigma = f.noise.sigma(z[l]);
        entry.R = depthDenoisingRadius(image.camera, parameters, z[l]);
      }
      const double sigma = entry.sigma;
      const int R = entry.R;
      sigmas[l] = sigma;
      b.g[l] = static_cast<float>(z[l] * z[l]);
      b.t[l] = static_cast<float>(f.range * sigma);
      b.scale[l] = static_cast<float>(z[l] * z[l] / (f.range * sigma));
      b.allowance[l] = static_cast<float>(parameters.slope_allowance * z[l] * f.pixel_scale);
      b.radius[l] = R - f.low;
      b.reach = std::max(b.reach, R / f.stride);
      tally.radius_min = std::min(tally.radius_min, R);
      tally.radius_max = std::max(tally.radius_max, R);
    }
    if (!any)
      continue;
    LanePlanes plane;
    fitBlock(f, b, plane);
    for (int l = 0; l < P; ++l)
      if (b.wp[l] == b.wp[l])
        finishPixel(parameters, z[l], sigmas[l], plane.ok[l / 8][l % 8] != 0, plane.a[l / 8][l % 8],
                    depth_out[static_cast<std::size_t>(v) * W + u0 + l], tally);
  }
}

// The row loop built for each instruction set; the same bits from each (see the top of the file).
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx512f"))) void denoiseRowAvx512(const LaneFilter& f, int v, double* out, RowTally& tally,
                                                         KnownDepths& known)
{
  denoiseRowBody<F16>(f, v, out, tally, known);
}
__attribute__((target("avx2"))) void denoiseRowAvx2(const LaneFilter& f, int v, double* out, RowTally& tally,
                                                     KnownDepths& known)
{
  denoiseRowBody<F8>(f, v, out, tally, known);
}
#endif
void denoiseRowPortable(const LaneFilter& f, int v, double* out, RowTally& tally, KnownDepths& known)
{
  denoiseRowBody<F8>(f, v, out, tally, known);
}

using RowFunction = void (*)(const LaneFilter&, int, double*, RowTally&, KnownDepths&);

RowFunction rowFunction()
{
#if defined(__x86_64__) && defined(__GNUC__)
  switch (detail::activeSimdKernels()) {
  case detail::SimdKernels::Avx512:
    return denoiseRowAvx512;
  case detail::SimdKernels::Avx2:
    return denoiseRowAvx2;
  default:
    break;
  }
#endif
  return denoiseRowPortable;
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
  if (image.width > static_cast<std::size_t>(std::numeric_limits<int>::max() / 4) ||
      image.height > static_cast<std::size_t>(std::numeric_limits<int>::max() / 4))
    throw Error("denoiseDepthImage: the depth image is too large");
  // The kernel's reach: its largest radius (max_radius, or min_radius when larger) over the stride.
  const int largest_radius = std::max(std::max(1, parameters.min_radius), parameters.max_radius);
  if (largest_radius / std::max(1, parameters.window_stride) > kMaxWindowReach || parameters.seed_radius > kMaxWindowReach)
    throw Error("denoiseDepthImage: the window reaches more than " + std::to_string(kMaxWindowReach) +
                " samples from its pixel (max(min_radius, max_radius) / window_stride and seed_radius are limited to it)");

  const int threads = parameters.num_threads > 0 ? parameters.num_threads : omp_get_max_threads();
  std::vector<float> inverse(n);
  std::size_t measured = 0;
#pragma omp parallel for schedule(static) num_threads(threads) reduction(+ : measured)
  for (std::size_t i = 0; i < n; ++i) {
    const double z = image.depth[i];
    const bool ok = image.valid[i] && z > 0.0 && std::isfinite(z);
    inverse[i] = ok ? static_cast<float>(1.0 / z) : std::numeric_limits<float>::quiet_NaN();
    measured += ok ? 1 : 0;
  }
  report.measured = measured;
  depth_out.assign(n, std::numeric_limits<double>::quiet_NaN());
  if (measured == 0) {
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return;
  }
  // The report's depth range from an even sample of up to 65,536 measured pixels.
  std::vector<double> depths;
  const std::size_t every = std::max<std::size_t>(1, measured / 65536);
  depths.reserve(measured / every + 1);
  for (std::size_t i = 0, seen = 0; i < n; ++i)
    if (inverse[i] == inverse[i] && seen++ % every == 0)
      depths.push_back(image.depth[i]);
  depthRange(image, parameters, std::move(depths), report);

  LaneFilter filter{image, noise, parameters, Grid(), 1, 1, 1, 2, 0, 16, 6, {}, {}, {}, 0.0, 0.0};
  prepareLaneFilter(filter, inverse);
  const RowFunction row_function = rowFunction();
  const int H = static_cast<int>(image.height);
  // Each row's tally is kept and the rows added in order afterwards: an OpenMP reduction of the
  // squared shifts would add them in the order the threads finish, and the report's last bits would
  // depend on the thread count.
  std::vector<RowTally> rows(static_cast<std::size_t>(H));
#pragma omp parallel num_threads(threads)
  {
    KnownDepths known;  // each thread's own
#pragma omp for schedule(dynamic, 4)
    for (int v = 0; v < H; ++v)
      row_function(filter, v, depth_out.data(), rows[static_cast<std::size_t>(v)], known);
  }
  double shift2 = 0.0;
  int radius_min = std::numeric_limits<int>::max(), radius_max = 0;
  for (const RowTally& row : rows) {
    report.moved += row.moved;
    report.left += row.left;
    report.clamped += row.clamped;
    shift2 += row.shift2;
    radius_min = std::min(radius_min, row.radius_min);
    radius_max = std::max(radius_max, row.radius_max);
  }
  report.rms_shift_sigmas = report.moved ? std::sqrt(shift2 / static_cast<double>(report.moved)) : 0.0;
  report.radius_min = std::min(radius_min, radius_max);
  report.radius_max = radius_max;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace patchdict
}  // namespace pcl
