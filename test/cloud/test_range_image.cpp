// Spinning-LiDAR range images (range_image.h, range_image_repair.h, sensor_model.h): a synthetic
// Ouster-like sensor (32 beams, 512 columns, negative azimuth step, per-beam azimuth offsets, beam
// origins on a 15.8 mm circle 36 mm up) ray-cast into a closed room with a box, its ranges noisy
// (σ = 1 cm, optionally stored in 8 mm steps). Checked against the truth: the fitted beams, the
// noise law, the fill of dropouts, the denoising along the beams, the model's text form, and the
// GeometricCloudInpainter's spinning path on pcl::PointXYZI frames.
#include "test_support.h"

#include <pcl_patchdict/cloud/geometric_cloud_inpainter.h>
#include <pcl_patchdict/cloud/range_image.h>
#include <pcl_patchdict/cloud/range_image_repair.h>
#include <pcl_patchdict/cloud/sensor_model.h>
#include <pcl_patchdict/core/error.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace {

using pcl::patchdict::RangeImage;
using pcl::patchdict::RangeNoiseModel;
using pcl::patchdict::SensorModel;
using pcl::patchdict::SpinningSensorModel;

constexpr double kPi = 3.14159265358979323846;
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

double degrees(double d) { return d * kPi / 180.0; }

double wrap(double a)
{
  a = std::fmod(a + kPi, 2.0 * kPi);
  return a < 0.0 ? a + kPi : a - kPi;
}

// Surfaces of the room, as labelled by the ray caster.
enum Surface { kSky = -1, kGround = 0, kFrontWall = 1, kBackWall = 2, kLeftWall = 3, kRightWall = 4, kBox = 5 };

/** The true sensor: 32 beams from +15° to −15° (row 0 up, slightly uneven), 512 columns over a whole
  * turn with a negative step (Ouster's), column 0 looking backwards, beam offsets of ±0.03°. */
SpinningSensorModel trueSensor(std::size_t width = 512, std::size_t height = 32, double top = 15.0)
{
  SpinningSensorModel m;
  m.width = width;
  m.height = height;
  for (std::size_t b = 0; b < height; ++b) {
    m.elevation.push_back(degrees(top - 2.0 * top * double(b) / double(height - 1) + 0.01 * std::sin(1.7 * double(b))));
    m.azimuth_offset.push_back(degrees(0.03 * std::sin(2.3 * double(b) + 0.5)));
  }
  m.azimuth_start = kPi - 0.001;
  m.azimuth_step = -2.0 * kPi / double(width);
  m.beam_radius = 0.0158;
  m.beam_height = 0.036;
  m.wraps = true;
  m.valid = true;
  return m;
}

/** The room, in the sensor's frame: ground z = −1.7, walls x = 12 and −8, y = 10 and −6 up to
  * z = 2.5 (the sky above them), a box [6, 7] × [2, 4] × [−1.7, 0.8] before the front wall. */
double castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& u, int& surface)
{
  const double ground = -1.7, top = 2.5;
  double best = kInf;
  surface = kSky;
  const auto take = [&](double t, int id) {
    if (t > 0.0 && t < best) {
      best = t;
      surface = id;
    }
  };
  if (u.z() < 0.0)
    take((ground - o.z()) / u.z(), kGround);
  const auto wall = [&](int axis, double at, int id) {
    if (u(axis) == 0.0)
      return;
    const double t = (at - o(axis)) / u(axis);
    const Eigen::Vector3d p = o + t * u;
    if (t > 0.0 && p.z() >= ground && p.z() <= top)
      take(t, id);
  };
  wall(0, 12.0, kFrontWall);
  wall(0, -8.0, kBackWall);
  wall(1, 10.0, kLeftWall);
  wall(1, -6.0, kRightWall);
  // The box: slabs.
  const Eigen::Vector3d lo(6.0, 2.0, ground), hi(7.0, 4.0, 0.8);
  double t0 = 0.0, t1 = kInf;
  for (int k = 0; k < 3; ++k) {
    if (u(k) == 0.0) {
      if (o(k) < lo(k) || o(k) > hi(k))
        t0 = kInf;
      continue;
    }
    double a = (lo(k) - o(k)) / u(k), b = (hi(k) - o(k)) / u(k);
    if (a > b)
      std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 <= t1 && t0 > 0.0)
    take(t0, kBox);
  return best;
}

/** A frame of the sensor: true ranges and surfaces, and the sensed points (range noise σ along the
  * ray, then stored in steps of `quantum` if > 0; NaN where the ray meets nothing). With
  * angle_jitter > 0 each point is sensed along a ray turned by Gaussian errors of that σ (radians) in
  * azimuth and elevation (encoder jitter: the points are then off their rays). */
struct Scan {
  SpinningSensorModel sensor;
  std::vector<double> truth;  ///< +inf where the sky
  std::vector<int> surface;
  std::vector<Eigen::Vector3d> points;
  std::size_t W = 0, H = 0;

  std::size_t at(std::size_t row, std::size_t column) const { return row * W + column % W; }
  /** Pixels of the disc around (row, column), the azimuth wrapping, rows clipped. */
  std::vector<std::size_t> disc(long row, long column, double radius) const
  {
    std::vector<std::size_t> pixels;
    const long r = static_cast<long>(std::ceil(radius));
    for (long db = -r; db <= r; ++db)
      for (long dc = -r; dc <= r; ++dc) {
        const long b = row + db;
        if (b < 0 || b >= long(H) || double(db * db + dc * dc) > radius * radius)
          continue;
        pixels.push_back(std::size_t(b) * W + std::size_t((column + dc + 8 * long(W)) % long(W)));
      }
    std::sort(pixels.begin(), pixels.end());
    return pixels;
  }
  void erase(const std::vector<std::size_t>& pixels)
  {
    for (const std::size_t i : pixels)
      points[i].setConstant(kNaN);
  }
};

Scan scan(const SpinningSensorModel& sensor, double sigma, double quantum, unsigned seed, double angle_jitter = 0.0)
{
  Scan s;
  s.sensor = sensor;
  s.W = sensor.width;
  s.H = sensor.height;
  const std::size_t n = s.W * s.H;
  s.truth.assign(n, kInf);
  s.surface.assign(n, kSky);
  s.points.assign(n, Eigen::Vector3d::Constant(kNaN));
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t b = 0; b < s.H; ++b)
    for (std::size_t c = 0; c < s.W; ++c) {
      const std::size_t i = b * s.W + c;
      const Eigen::Vector3d o = sensor.rayOrigin(b, c), u = sensor.direction(b, c);
      const double r = castRay(o, u, s.surface[i]);
      const double noise = gauss(rng);  // drawn for every pixel: frames differ only by the seed
      const double da = angle_jitter * gauss(rng), de = angle_jitter * gauss(rng);
      if (!std::isfinite(r))
        continue;
      s.truth[i] = r;
      double sensed = r + sigma * noise;
      if (quantum > 0.0)
        sensed = std::round(sensed / quantum) * quantum;
      if (angle_jitter > 0.0) {
        const double a = sensor.azimuth(b, c) + da, e = sensor.elevation[b] + de;
        const Eigen::Vector3d origin(sensor.beam_radius * std::cos(a), sensor.beam_radius * std::sin(a),
                                     sensor.beam_height);
        s.points[i] = origin + sensed * Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      } else {
        s.points[i] = o + sensed * u;
      }
    }
  return s;
}

/** True when every pixel within `rows` beams and `columns` columns of i lies on surface i's. */
bool onOneSurface(const Scan& s, std::size_t i, int rows, int columns)
{
  const long b0 = long(i / s.W), c0 = long(i % s.W);
  for (long db = -rows; db <= rows; ++db)
    for (long dc = -columns; dc <= columns; ++dc) {
      const long b = b0 + db;
      if (b < 0 || b >= long(s.H))
        return false;
      if (s.surface[s.at(std::size_t(b), std::size_t(c0 + dc + long(s.W)))] != s.surface[i])
        return false;
    }
  return true;
}

// One shared frame per noise setting (the ray casting is cheap, but done once).
const Scan& noisyScan()
{
  static const Scan s = scan(trueSensor(), 0.01, 0.0, 11);
  return s;
}
const Scan& quantisedScan()
{
  static const Scan s = scan(trueSensor(), 0.01, 0.008, 12);
  return s;
}

RangeImage imageOf(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& model)
{
  return pcl::patchdict::makeRangeImage(points, model);
}

// ---------------------------------------------------------------------------------------------------
// fitSpinningSensor

struct FitErrors {
  double elevation = 0.0, step = 0.0, offset = 0.0, azimuth = 0.0, radius = 0.0, height = 0.0;
};

FitErrors fitErrors(const SpinningSensorModel& m, const SpinningSensorModel& t)
{
  FitErrors e;
  for (std::size_t b = 0; b < t.height; ++b) {
    e.elevation = std::max(e.elevation, std::abs(m.elevation[b] - t.elevation[b]));
    // The offsets are relative to the start the fit chose: compare them beam to beam.
    e.offset = std::max(e.offset, std::abs(wrap((m.azimuth_offset[b] - m.azimuth_offset[0]) -
                                                (t.azimuth_offset[b] - t.azimuth_offset[0]))));
    for (std::size_t c = 0; c < t.width; c += 7)
      e.azimuth = std::max(e.azimuth, std::abs(wrap(m.azimuth(b, c) - t.azimuth(b, c))));
  }
  e.step = std::abs(m.azimuth_step - t.azimuth_step);
  e.radius = std::abs(m.beam_radius - t.beam_radius);
  e.height = std::abs(m.beam_height - t.beam_height);
  std::printf("[ observed ] fit errors: elevation %.3g rad, step %.3g rad, offsets %.3g rad, pixel azimuth %.3g rad, "
              "beam radius %.3g m, beam height %.3g m; rms %.3g rad, off-ray %zu\n",
              e.elevation, e.step, e.offset, e.azimuth, e.radius, e.height, m.rms_radians, m.off_ray);
  return e;
}

// Range noise (and its 8 mm steps) moves each point along its own ray: the fit is exact.
TEST(SpinningSensorFit, RangeNoiseLeavesTheFitExact)
{
  for (const Scan* s : {&noisyScan(), &quantisedScan()}) {
    const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s->points, s->W, s->H);
    ASSERT_TRUE(m.valid) << m.failure;
    EXPECT_TRUE(m.wraps);
    EXPECT_EQ(m.off_ray, 0u);
    const FitErrors e = fitErrors(m, s->sensor);
    EXPECT_LT(e.elevation, 1e-9);
    EXPECT_LT(e.step, 1e-12);
    EXPECT_LT(e.azimuth, 1e-9);
    EXPECT_LT(e.radius, 1e-9);
    EXPECT_LT(e.height, 1e-9);
    EXPECT_LT(m.rms_radians, 1e-9);
  }
}

// With the rays themselves jittered (σ = 1e-4 rad ≈ 0.006° in azimuth and elevation, 1 mm at 10 m)
// the fit has to average: elevations to 1e-4 rad, the beam origins to 1 mm.
TEST(SpinningSensorFit, RecoversBeamsAzimuthsAndBeamOriginsOfAJitteredNoisyScan)
{
  const Scan s = scan(trueSensor(), 0.01, 0.0, 31, 1e-4);
  const SpinningSensorModel& t = s.sensor;
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid) << m.failure;
  EXPECT_TRUE(m.failure.empty());
  EXPECT_EQ(m.width, s.W);
  EXPECT_EQ(m.height, s.H);
  EXPECT_TRUE(m.wraps);
  EXPECT_EQ(m.off_ray, 0u);
  ASSERT_EQ(m.elevation.size(), s.H);
  ASSERT_EQ(m.azimuth_offset.size(), s.H);
  const FitErrors e = fitErrors(m, t);
  EXPECT_LT(e.elevation, 1e-4);
  // The step is the median of the neighbours' azimuth differences (each jittered by √2 × 1e-4): its
  // error (observed 9e-7) adds up over the turn (×511: 5e-4 rad, 4 % of a step) and biases the
  // beams' offsets (observed 1.4e-4) and the pixels' azimuths (3.6e-4): see the disabled test below.
  EXPECT_LT(e.step, 2e-6);
  EXPECT_LT(e.offset, 2.5e-4);  // half the offsets' amplitude (±0.03° = ±5.2e-4 rad)
  EXPECT_LT(e.azimuth, 6e-4);   // 5 % of a step
  EXPECT_LT(e.radius, 1e-3);
  EXPECT_LT(e.height, 1e-3);
  EXPECT_GT(m.rms_radians, 0.5 * std::sqrt(2.0) * 1e-4);  // the jitter, measured
  EXPECT_LT(m.rms_radians, 2.0 * std::sqrt(2.0) * 1e-4);
  EXPECT_NEAR(m.beamGap(), t.beamGap(), 1e-4);

  // On its own frame the model's range image is the truth up to the noise.
  const RangeImage image = imageOf(s.points, m);
  std::size_t sky = 0;
  double squares = 0.0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    ASSERT_EQ(image.valid[i] != 0, s.surface[i] != kSky) << i;
    if (!image.valid[i]) {
      ++sky;
      EXPECT_TRUE(std::isnan(image.range[i]));
      continue;
    }
    squares += (image.range[i] - s.truth[i]) * (image.range[i] - s.truth[i]);
  }
  EXPECT_GT(sky, 500u);  // the scene has sky above the walls
  EXPECT_EQ(image.measured(), s.points.size() - sky);
  const double rms = std::sqrt(squares / double(image.measured()));
  std::printf("[ observed ] range rms on the fitted rays %.4g m, sky %zu px\n", rms, sky);
  EXPECT_GT(rms, 0.009);
  EXPECT_LT(rms, 0.011);
}

// With 1e-4 rad of angle jitter a median neighbour step would err by ~9e-7 rad, 4.8e-4 rad over 511
// columns, and bias the per-beam offsets by a quarter of their size: a whole turn's step is 2π/W.
TEST(SpinningSensorFit, JitteredScanGivesTheOffsetsToATenth)
{
  const Scan s = scan(trueSensor(), 0.01, 0.0, 31, 1e-4);
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid) << m.failure;
  const FitErrors e = fitErrors(m, s.sensor);
  EXPECT_LT(e.step, 1e-7);
  EXPECT_LT(e.offset, 5e-5);
  EXPECT_LT(e.azimuth, 1e-4);
}

TEST(SpinningSensorFit, ShuffledRowsAreNotBeams)
{
  Scan s = noisyScan();
  std::vector<std::size_t> order(s.H);
  for (std::size_t b = 0; b < s.H; ++b)
    order[b] = b;
  std::mt19937 rng(5);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<Eigen::Vector3d> shuffled(s.points.size());
  for (std::size_t b = 0; b < s.H; ++b)
    for (std::size_t c = 0; c < s.W; ++c)
      shuffled[b * s.W + c] = s.points[order[b] * s.W + c];
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(shuffled, s.W, s.H);
  EXPECT_FALSE(m.valid);
  EXPECT_FALSE(m.failure.empty());
  EXPECT_THROW(pcl::patchdict::makeRangeImage(shuffled, m), pcl::patchdict::Error);
  // Two neighbouring rows swapped are enough.
  std::vector<Eigen::Vector3d> swapped = s.points;
  std::swap_ranges(swapped.begin() + 10 * long(s.W), swapped.begin() + 11 * long(s.W), swapped.begin() + 11 * long(s.W));
  const SpinningSensorModel m2 = pcl::patchdict::fitSpinningSensor(swapped, s.W, s.H);
  EXPECT_FALSE(m2.valid);
  EXPECT_NE(m2.failure.find("monotonic"), std::string::npos) << m2.failure;
}

TEST(SpinningSensorFit, EmptyDegenerateAndTinyGridsFailWithAReason)
{
  const std::size_t W = 512, H = 32;
  const auto fails = [](const std::vector<Eigen::Vector3d>& points, std::size_t w, std::size_t h) {
    const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(points, w, h);
    EXPECT_FALSE(m.valid);
    EXPECT_FALSE(m.failure.empty());
    return m.failure;
  };
  fails(std::vector<Eigen::Vector3d>(W * H, Eigen::Vector3d::Constant(kNaN)), W, H);
  fails(std::vector<Eigen::Vector3d>(W * H, Eigen::Vector3d::Zero()), W, H);
  // 15 measured points of the real scan, the rest NaN.
  const Scan& s = noisyScan();
  std::vector<Eigen::Vector3d> few(W * H, Eigen::Vector3d::Constant(kNaN));
  std::size_t kept = 0;
  for (std::size_t i = 0; i < s.points.size() && kept < 15; i += 997)
    if (s.points[i].allFinite()) {
      few[i] = s.points[i];
      ++kept;
    }
  ASSERT_EQ(kept, 15u);
  EXPECT_NE(fails(few, W, H).find("16"), std::string::npos);
  // Infinite coordinates, a grid that does not match the points, a single column, empty input.
  fails(std::vector<Eigen::Vector3d>(W * H, Eigen::Vector3d::Constant(kInf)), W, H);
  fails(s.points, W, H + 1);
  fails(std::vector<Eigen::Vector3d>(H, Eigen::Vector3d(1.0, 0.0, 0.0)), 1, H);
  fails({}, 0, 0);
  // Every point the same.
  fails(std::vector<Eigen::Vector3d>(W * H, Eigen::Vector3d(3.0, 1.0, -0.5)), W, H);
}

TEST(SpinningSensorFit, DuplicatedColumnsAreNotAzimuthSteps)
{
  const Scan& s = noisyScan();
  // Every column twice: a 1024-column grid whose steps alternate 0 and 2π/512.
  std::vector<Eigen::Vector3d> doubled(2 * s.points.size());
  for (std::size_t b = 0; b < s.H; ++b)
    for (std::size_t c = 0; c < s.W; ++c)
      doubled[b * 2 * s.W + 2 * c] = doubled[b * 2 * s.W + 2 * c + 1] = s.points[b * s.W + c];
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(doubled, 2 * s.W, s.H);
  EXPECT_FALSE(m.valid) << "azimuth step " << m.azimuth_step << ", off-ray " << m.off_ray;
  EXPECT_FALSE(m.failure.empty());
  std::printf("[ observed ] doubled columns: %s\n", m.failure.c_str());
  // The same 512-column grid holding 256 azimuths twice each (an upsampled half-resolution scan).
  std::vector<Eigen::Vector3d> halved(s.points.size());
  for (std::size_t b = 0; b < s.H; ++b)
    for (std::size_t c = 0; c < s.W; ++c)
      halved[b * s.W + c] = s.points[b * s.W + (c / 2) * 2];
  const SpinningSensorModel m2 = pcl::patchdict::fitSpinningSensor(halved, s.W, s.H);
  EXPECT_FALSE(m2.valid) << "azimuth step " << m2.azimuth_step << ", off-ray " << m2.off_ray;
  EXPECT_FALSE(m2.failure.empty());
  std::printf("[ observed ] 256 azimuths twice: %s\n", m2.failure.c_str());
}

// A plane seen by a 64 × 48 pinhole camera (f = 50 px), in the camera's frame (z forward) and turned
// so that the camera looks along x with its rows horizontal (z up): neither is a spinning sensor.
TEST(SpinningSensorFit, APinholeImageIsNotASpinningSensor)
{
  const std::size_t W = 64, H = 48;
  const double f = 50.0, cx = 31.5, cy = 23.5;
  std::vector<Eigen::Vector3d> camera(W * H), turned(W * H);
  for (std::size_t v = 0; v < H; ++v)
    for (std::size_t u = 0; u < W; ++u) {
      const Eigen::Vector3d ray((double(u) - cx) / f, (double(v) - cy) / f, 1.0);
      const Eigen::Vector3d n = Eigen::Vector3d(0.1, -0.3, 1.0).normalized();
      const Eigen::Vector3d p = ray * (2.0 / n.dot(ray));
      camera[v * W + u] = p;
      turned[v * W + u] = Eigen::Vector3d(p.z(), -p.x(), -p.y());
    }
  for (const auto* points : {&camera, &turned}) {
    const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(*points, W, H);
    EXPECT_FALSE(m.valid) << "taken for a spinning sensor: step " << m.azimuth_step << ", rms " << m.rms_radians;
    EXPECT_FALSE(m.failure.empty());
    std::printf("[ observed ] pinhole grid: %s\n", m.failure.c_str());
  }
  // The sensor model of the grid is the pinhole camera it is.
  const SensorModel model = pcl::patchdict::estimateSensorModel(camera, W, H);
  EXPECT_EQ(model.kind, SensorModel::Kind::Pinhole);
  EXPECT_NEAR(model.camera.fx, f, 1e-3);
}

TEST(SpinningSensorFit, AnotherSensorsFrameDoesNotFitAGivenModel)
{
  const Scan& s = noisyScan();
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid);
  const Scan wide = scan(trueSensor(512, 32, 22.5), 0.01, 0.0, 3);  // ±22.5°: other elevations
  EXPECT_THROW(pcl::patchdict::makeRangeImage(wide.points, m), pcl::patchdict::Error);
  const Scan narrow = scan(trueSensor(256, 32), 0.01, 0.0, 3);  // another width
  EXPECT_THROW(pcl::patchdict::makeRangeImage(narrow.points, m), pcl::patchdict::Error);
  // A few points off their rays are set aside, counted, and the rest kept.
  std::vector<Eigen::Vector3d> points = s.points;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < points.size(); i += 101)
    if (points[i].allFinite()) {
      points[i] = Eigen::Vector3d(points[i].y(), -points[i].x(), points[i].z());  // 90° off in azimuth
      ++moved;
    }
  const RangeImage image = pcl::patchdict::makeRangeImage(points, m);
  EXPECT_EQ(image.model.off_ray, moved);
  EXPECT_EQ(image.measured(), imageOf(s.points, m).measured() - moved);
}

// ---------------------------------------------------------------------------------------------------
// estimateRangeNoise

TEST(RangeImageNoise, EstimatesSigmaAndFindsTheRangeStep)
{
  const Scan& s = noisyScan();
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid);
  const RangeNoiseModel noise = pcl::patchdict::estimateRangeNoise(imageOf(s.points, m));
  std::printf("[ observed ] plain: coefficient %.4g exponent %.3g (fitted %d) sigma(10 m) %.4g quantum %g "
              "samples %zu ranges %.3g-%.3g\n",
              noise.coefficient, noise.exponent, int(noise.exponent_fitted), noise.sigma(10.0), noise.quantum,
              noise.samples, noise.range_low, noise.range_high);
  const double at10 = noise.coefficient * std::pow(10.0, noise.exponent);
  EXPECT_GT(at10, 0.01 / 1.25);  // observed 1.05 cm
  EXPECT_LT(at10, 0.01 * 1.25);
  EXPECT_LT(std::abs(noise.sigma(5.0) / noise.sigma(15.0) - 1.0), 0.5);  // the true σ does not grow
  EXPECT_EQ(noise.quantum, 0.0);
  EXPECT_GT(noise.samples, 2000u);

  const Scan& q = quantisedScan();
  const SpinningSensorModel mq = pcl::patchdict::fitSpinningSensor(q.points, q.W, q.H);
  ASSERT_TRUE(mq.valid) << mq.failure;
  const RangeNoiseModel quantised = pcl::patchdict::estimateRangeNoise(imageOf(q.points, mq));
  std::printf("[ observed ] 8 mm steps: coefficient %.4g exponent %.3g sigma(10 m) %.4g quantum %g\n",
              quantised.coefficient, quantised.exponent, quantised.sigma(10.0), quantised.quantum);
  EXPECT_DOUBLE_EQ(quantised.quantum, 0.008);
  const double q10 = quantised.coefficient * std::pow(10.0, quantised.exponent);
  const double total = std::sqrt(0.01 * 0.01 + 0.008 * 0.008 / 12.0);  // the noise plus the step's
  EXPECT_GT(q10, total / 1.25);  // observed 1.10 cm for 1.03
  EXPECT_LT(q10, total * 1.25);
}

TEST(RangeImageNoise, RangeProportionalNoiseGivesAnExponentNearOne)
{
  // σ = 1 mm per metre: the estimate's exponent and σ(10 m).
  Scan s = scan(trueSensor(), 0.0, 0.0, 21);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (s.points[i].allFinite()) {
      const std::size_t b = i / s.W, c = i % s.W;
      s.points[i] = s.sensor.pointAt(b, c, s.truth[i] * (1.0 + 0.001 * gauss(rng)));
    }
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid) << m.failure;
  const RangeNoiseModel noise = pcl::patchdict::estimateRangeNoise(imageOf(s.points, m));
  std::printf("[ observed ] sigma = 1e-3 rho: exponent %.3g (fitted %d), sigma(10 m) %.4g, ranges %.3g-%.3g\n",
              noise.exponent, int(noise.exponent_fitted), noise.sigma(10.0), noise.range_low, noise.range_high);
  ASSERT_TRUE(noise.exponent_fitted);
  EXPECT_NEAR(noise.exponent, 1.0, 0.35);
  EXPECT_GT(noise.sigma(10.0), 0.01 / 1.5);
  EXPECT_LT(noise.sigma(10.0), 0.01 * 1.5);
}

// ---------------------------------------------------------------------------------------------------
// fillRangeImageHoles

struct Hole {
  long row, column;
  double radius;
  int surface;
};

// Dropouts on the four walls (one across the azimuth's wrap, column 0) and one straddling the box's
// edge in front of the front wall.
const Hole kWallHoles[] = {{10, 256, 3.0, kFrontWall}, {12, 1, 3.0, kBackWall}, {14, 128, 2.0, kLeftWall},
                           {9, 384, 4.0, kRightWall}};
const Hole kEdgeHole{14, 231, 3.0, kBox};

TEST(RangeImageFill, FillsDropoutsOnWallsAndLeavesEdgesAndSkyOpen)
{
  Scan s = noisyScan();
  std::vector<std::size_t> punched;
  for (const Hole& h : kWallHoles) {
    const auto pixels = s.disc(h.row, h.column, h.radius);
    // The scene is as intended: the disc and two pixels around it on the one wall.
    for (const std::size_t i : s.disc(h.row, h.column, h.radius + 2.0))
      ASSERT_EQ(s.surface[i], h.surface) << "hole at " << h.row << ", " << h.column;
    s.erase(pixels);
    punched.insert(punched.end(), pixels.begin(), pixels.end());
  }
  const auto edge = s.disc(kEdgeHole.row, kEdgeHole.column, kEdgeHole.radius);
  std::set<int> edge_surfaces;
  for (const std::size_t i : s.disc(kEdgeHole.row, kEdgeHole.column, kEdgeHole.radius + 1.0))
    edge_surfaces.insert(s.surface[i]);
  ASSERT_TRUE(edge_surfaces.count(kBox) && edge_surfaces.count(kFrontWall));
  s.erase(edge);

  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid) << m.failure;
  const RangeImage image = imageOf(s.points, m);
  const RangeNoiseModel noise = pcl::patchdict::estimateRangeNoise(image);
  std::vector<std::size_t> pixels;
  std::vector<double> ranges;
  pcl::patchdict::RangeFillReport report;
  pcl::patchdict::fillRangeImageHoles(image, noise, pcl::patchdict::RangeFillParameters{}, pixels, ranges, report);
  ASSERT_EQ(pixels.size(), ranges.size());
  EXPECT_TRUE(std::is_sorted(pixels.begin(), pixels.end()));
  EXPECT_EQ(report.pixels_filled, pixels.size());

  // Exactly the wall dropouts are filled: every punched pixel, nothing else.
  std::vector<std::size_t> expected = punched;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(pixels, expected);
  EXPECT_EQ(report.holes_filled, 4u);
  EXPECT_GE(report.touching_border, 1u);   // the sky
  EXPECT_GE(report.not_one_surface, 1u);   // the box's edge
  const std::vector<double> nearest = pcl::patchdict::nearestMeasuredRange(image);
  double sum = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    const std::size_t i = pixels[k];
    ASSERT_NE(s.surface[i], kSky);
    EXPECT_GE(ranges[k], pcl::patchdict::freeSpaceBound(nearest[i], m.azimuth_step, 2.0, 0.008)) << i;
    sum += std::abs(ranges[k] - s.truth[i]);
    worst = std::max(worst, std::abs(ranges[k] - s.truth[i]));
  }
  const double mean = sum / double(std::max<std::size_t>(1, pixels.size()));
  std::printf("[ observed ] fill: %zu pixels, mean |error| %.4g m, worst %.4g m, regions %zu, border %zu, "
              "not one surface %zu, grazing %zu, dropped %zu\n",
              pixels.size(), mean, worst, report.regions, report.touching_border, report.not_one_surface,
              report.grazing, report.free_space_dropped);
  EXPECT_LT(mean, 1.5 * 0.01);  // observed 4.7 mm
  EXPECT_LT(worst, 6.0 * 0.01);  // observed 3.3 cm
  // No sky pixel, and no pixel of the edge's hole, is filled.
  for (const std::size_t i : edge)
    EXPECT_FALSE(std::binary_search(pixels.begin(), pixels.end(), i)) << i;

  // Deterministic, and appended to what the vectors held.
  std::vector<std::size_t> again_pixels{7};
  std::vector<double> again_ranges{1.0};
  pcl::patchdict::RangeFillReport again;
  pcl::patchdict::fillRangeImageHoles(image, noise, pcl::patchdict::RangeFillParameters{}, again_pixels, again_ranges,
                                      again);
  ASSERT_EQ(again_pixels.size(), pixels.size() + 1);
  EXPECT_TRUE(std::equal(pixels.begin(), pixels.end(), again_pixels.begin() + 1));
  EXPECT_EQ(0, std::memcmp(ranges.data(), again_ranges.data() + 1, ranges.size() * sizeof(double)));
  // A bound on the holes' size leaves them open.
  pcl::patchdict::RangeFillParameters small;
  small.max_hole_pixels = 12;  // the discs hold 13, 29, 29 and 49 pixels
  std::vector<std::size_t> few;
  std::vector<double> few_ranges;
  pcl::patchdict::RangeFillReport few_report;
  pcl::patchdict::fillRangeImageHoles(image, noise, small, few, few_ranges, few_report);
  EXPECT_TRUE(few.empty());
  EXPECT_GE(few_report.too_large, 4u);
}

// Fills a ground scan's dropouts (discs at column 200, 40° left of ahead, where the ground reaches
// 12 m before the walls) with `parameters`; returns the filled pixels, their ranges in `ranges`.
std::vector<std::size_t> fillGroundHoles(double sigma, const std::vector<Hole>& holes,
                                         const pcl::patchdict::RangeFillParameters& parameters, Scan& s,
                                         std::vector<std::size_t>& punched, std::vector<double>& ranges,
                                         pcl::patchdict::RangeFillReport& report)
{
  s = scan(trueSensor(), sigma, 0.0, 11);
  punched.clear();
  for (const Hole& h : holes) {
    for (const std::size_t i : s.disc(h.row, h.column, h.radius + 1.0))
      EXPECT_EQ(s.surface[i], kGround) << "hole at " << h.row << ", " << h.column;
    const auto pixels = s.disc(h.row, h.column, h.radius);
    s.erase(pixels);
    punched.insert(punched.end(), pixels.begin(), pixels.end());
  }
  std::sort(punched.begin(), punched.end());
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  EXPECT_TRUE(m.valid) << m.failure;
  const RangeImage image = imageOf(s.points, m);
  RangeNoiseModel noise = pcl::patchdict::estimateRangeNoise(image);
  if (sigma == 0.0)
    noise.coefficient = 0.01;  // a noise-free scan: the law of the noisy one
  std::vector<std::size_t> pixels;
  ranges.clear();
  report = {};
  pcl::patchdict::fillRangeImageHoles(image, noise, parameters, pixels, ranges, report);
  return pixels;
}

// Dropouts on the ground in front of the sensor (rows 27-29: −11° to −13°, 7.7-9 m away, the ground
// seen at 77-79° from its normal, within max_incidence_degrees), filled with a wider rim spread than
// the default: along the beams the ground's range changes by cot(e)·Δe ≈ 7-9 % a beam, which the
// default rim_spread of 3 % reads as a discontinuity (see the disabled test below).
TEST(RangeImageFill, FillsDropoutsOnTheGroundWhenTheRimSpreadAllowsItsSlope)
{
  pcl::patchdict::RangeFillParameters parameters;
  parameters.rim_spread = 0.5;
  Scan s;
  std::vector<std::size_t> punched;
  std::vector<double> ranges;
  pcl::patchdict::RangeFillReport report;
  const std::vector<Hole> holes = {{27, 200, 1.0, kGround}, {28, 180, 1.0, kGround}, {28, 160, 1.0, kGround}};
  const auto pixels = fillGroundHoles(0.01, holes, parameters, s, punched, ranges, report);
  EXPECT_EQ(pixels, punched);
  EXPECT_EQ(report.holes_filled, 3u);
  double sum = 0.0, worst = 0.0;
  for (std::size_t k = 0; k < pixels.size(); ++k) {
    sum += std::abs(ranges[k] - s.truth[pixels[k]]);
    worst = std::max(worst, std::abs(ranges[k] - s.truth[pixels[k]]));
  }
  const double mean = sum / double(std::max<std::size_t>(1, pixels.size()));
  std::printf("[ observed ] ground fill (rim_spread 0.5): %zu of %zu pixels, mean |error| %.4g m, worst %.4g m\n",
              pixels.size(), punched.size(), mean, worst);
  EXPECT_LT(mean, 1.5 * 0.01);  // observed 3.0 mm
  EXPECT_LT(worst, 3.0 * 0.01);  // observed 7.6 mm
}

// By design, with the default parameters no dropout on this sensor's ground is filled: the rim test
// asks the rim's ranges to span at most rim_spread = 3 % of their median (the harmonic range-image
// fill's own test), and on the ground the range changes by cot(e)·Δe per beam (≈ 6.5 % at −15°,
// 9.7 % at −10° for a 0.97° beam gap), so a ground dropout's rim reads as a discontinuity. This
// holds the fills to what a rim determines (docs/real_sensor_scans.md, "Holes in a range image").
TEST(RangeImageFill, LeavesGroundDropoutsOpenWithDefaultParameters)
{
  Scan s;
  std::vector<std::size_t> punched;
  std::vector<double> ranges;
  pcl::patchdict::RangeFillReport report;
  const auto pixels = fillGroundHoles(0.01, {{27, 200, 1.0, kGround}, {28, 180, 1.0, kGround}},
                                      pcl::patchdict::RangeFillParameters{}, s, punched, ranges, report);
  for (const std::size_t i : punched)
    EXPECT_FALSE(std::binary_search(pixels.begin(), pixels.end(), i)) << i;
  EXPECT_GE(report.not_one_surface + report.grazing, 2u);
}

// A fill that its neighbours' measurements contradict is left open, never pushed off its surface:
// in a noise-free scan with a disc of radius 2 at row 28 on the ground, pixel (27, 200) has only
// row 26's measurements around it, 0.84 m farther along rays 1° higher, and its true range (9.0 m)
// is nearer than they allow. Every pixel that is filled is filled at its true range.
TEST(RangeImageFill, LeavesAFillTheBeamsContradictOpenInsteadOfPushingItBack)
{
  pcl::patchdict::RangeFillParameters parameters;
  parameters.rim_spread = 1.0;  // past the rim test, to reach the free-space bound
  Scan s;
  std::vector<std::size_t> punched;
  std::vector<double> ranges;
  pcl::patchdict::RangeFillReport report;
  const auto pixels = fillGroundHoles(0.0, {{28, 200, 2.0, kGround}}, parameters, s, punched, ranges, report);
  EXPECT_GE(report.free_space_dropped, 1u);
  EXPECT_EQ(pixels.size() + report.free_space_dropped, punched.size());
  EXPECT_GE(pixels.size(), punched.size() / 2);
  for (std::size_t k = 0; k < pixels.size(); ++k)
    EXPECT_NEAR(ranges[k], s.truth[pixels[k]], 1e-3) << "row " << pixels[k] / s.W << ", column " << pixels[k] % s.W;
}

// ---------------------------------------------------------------------------------------------------
// denoiseRangeImage

TEST(RangeImageDenoising, HalvesTheErrorOnPlanesAndNeverCutsIntoFreeSpace)
{
  const Scan& s = noisyScan();
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid) << m.failure;
  const RangeImage image = imageOf(s.points, m);
  const RangeNoiseModel noise = pcl::patchdict::estimateRangeNoise(image);
  pcl::patchdict::RangeDenoisingParameters parameters;
  parameters.num_threads = 1;
  std::vector<double> one, two;
  pcl::patchdict::RangeDenoisingReport report, report2;
  pcl::patchdict::denoiseRangeImage(image, noise, parameters, one, report);
  parameters.num_threads = 2;
  pcl::patchdict::denoiseRangeImage(image, noise, parameters, two, report2);
  ASSERT_EQ(one.size(), s.points.size());
  ASSERT_EQ(two.size(), one.size());
  EXPECT_EQ(0, std::memcmp(one.data(), two.data(), one.size() * sizeof(double)));
  EXPECT_EQ(report.moved, report2.moved);
  EXPECT_EQ(report.measured, image.measured());
  EXPECT_EQ(report.measured, report.moved + report.left);

  // The planes' pixels (their whole 7 × 3 window on the ground or one wall) and every pixel.
  double before = 0.0, after = 0.0, all_before = 0.0, all_after = 0.0;
  std::size_t count = 0, measured = 0;
  const std::vector<double> nearest = pcl::patchdict::nearestMeasuredRange(image);
  std::size_t closer = 0;
  for (std::size_t i = 0; i < one.size(); ++i) {
    if (!image.valid[i]) {
      EXPECT_TRUE(std::isnan(one[i]));
      continue;
    }
    ASSERT_TRUE(std::isfinite(one[i]));
    const double e0 = image.range[i] - s.truth[i], e1 = one[i] - s.truth[i];
    all_before += e0 * e0;
    all_after += e1 * e1;
    ++measured;
    if (one[i] < image.range[i]) {
      ++closer;
      EXPECT_GE(one[i], std::min(image.range[i], pcl::patchdict::freeSpaceBound(nearest[i], m.azimuth_step, 2.0, 0.008)))
          << i;
    }
    EXPECT_LE(std::abs(one[i] - image.range[i]), parameters.max_shift_sigmas * noise.sigma(image.range[i]) * (1 + 1e-12));
    if (s.surface[i] != kBox && onOneSurface(s, i, 1, 3)) {
      before += e0 * e0;
      after += e1 * e1;
      ++count;
    }
  }
  const double rms_before = std::sqrt(before / double(count)), rms_after = std::sqrt(after / double(count));
  const double all_rms_before = std::sqrt(all_before / double(measured));
  const double all_rms_after = std::sqrt(all_after / double(measured));
  std::printf("[ observed ] denoising: planes %zu px, rms %.4g -> %.4g m (%.2fx); all %zu px, rms %.4g -> %.4g m; "
              "moved %zu, clamped %zu, free space %zu, closer %zu, %.3f s\n",
              count, rms_before, rms_after, rms_before / rms_after, measured, all_rms_before, all_rms_after,
              report.moved, report.clamped, report.free_space_clamped, closer, report.seconds);
  EXPECT_GT(count, 8000u);
  EXPECT_GT(rms_before / rms_after, 2.5);  // observed 3.2
  EXPECT_LT(all_rms_after, all_rms_before);  // the box's edges and corners do not eat the gain
  EXPECT_GT(report.moved, measured * 9 / 10);
}

TEST(RangeImageDenoising, RejectsAMissingNoiseLawAndBadParameters)
{
  const Scan& s = noisyScan();
  const SpinningSensorModel m = pcl::patchdict::fitSpinningSensor(s.points, s.W, s.H);
  ASSERT_TRUE(m.valid);
  const RangeImage image = imageOf(s.points, m);
  std::vector<double> out;
  pcl::patchdict::RangeDenoisingReport report;
  EXPECT_THROW(pcl::patchdict::denoiseRangeImage(image, RangeNoiseModel{}, {}, out, report), pcl::patchdict::Error);
  RangeNoiseModel noise;
  noise.coefficient = 0.01;
  pcl::patchdict::RangeDenoisingParameters bad;
  bad.column_radius = -1;
  EXPECT_THROW(pcl::patchdict::denoiseRangeImage(image, noise, bad, out, report), pcl::patchdict::Error);
  bad = {};
  bad.min_neighbours = 2;
  EXPECT_THROW(pcl::patchdict::denoiseRangeImage(image, noise, bad, out, report), pcl::patchdict::Error);
  pcl::patchdict::RangeFillParameters fill;
  fill.max_incidence_degrees = 91.0;
  std::vector<std::size_t> pixels;
  std::vector<double> ranges;
  pcl::patchdict::RangeFillReport fill_report;
  EXPECT_THROW(pcl::patchdict::fillRangeImageHoles(image, noise, fill, pixels, ranges, fill_report),
               pcl::patchdict::Error);
}

// ---------------------------------------------------------------------------------------------------
// The sensor model's text

SensorModel spinningModel()
{
  const Scan& s = quantisedScan();
  SensorModel model = pcl::patchdict::estimateSensorModel(s.points, s.W, s.H);
  EXPECT_EQ(model.kind, SensorModel::Kind::Spinning) << model.failure;
  return model;
}

void expectSameSpinning(const SensorModel& a, const SensorModel& b)
{
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.spinning.width, b.spinning.width);
  EXPECT_EQ(a.spinning.height, b.spinning.height);
  EXPECT_EQ(a.spinning.elevation, b.spinning.elevation);  // every double, exactly
  EXPECT_EQ(a.spinning.azimuth_offset, b.spinning.azimuth_offset);
  EXPECT_EQ(a.spinning.azimuth_start, b.spinning.azimuth_start);
  EXPECT_EQ(a.spinning.azimuth_step, b.spinning.azimuth_step);
  EXPECT_EQ(a.spinning.beam_radius, b.spinning.beam_radius);
  EXPECT_EQ(a.spinning.beam_height, b.spinning.beam_height);
  EXPECT_EQ(a.spinning.wraps, b.spinning.wraps);
  EXPECT_EQ(a.range_noise.coefficient, b.range_noise.coefficient);
  EXPECT_EQ(a.range_noise.exponent, b.range_noise.exponent);
  EXPECT_EQ(a.range_noise.quantum, b.range_noise.quantum);
}

TEST(SensorModelText, RoundTripIsBitExact)
{
  const SensorModel model = spinningModel();
  ASSERT_EQ(model.kind, SensorModel::Kind::Spinning);
  EXPECT_EQ(model.range_noise.quantum, 0.008);
  const std::string text = pcl::patchdict::formatSensorModel(model);
  const SensorModel parsed = pcl::patchdict::parseSensorModel(text);
  EXPECT_TRUE(parsed.spinning.valid);
  expectSameSpinning(model, parsed);
  EXPECT_EQ(pcl::patchdict::formatSensorModel(parsed), text);
  test_support::TempDir dir;
  pcl::patchdict::saveSensorModel(model, dir.file("os.sensor"));
  EXPECT_EQ(test_support::readFile(dir.file("os.sensor")), text);
  const SensorModel loaded = pcl::patchdict::loadSensorModel(dir.file("os.sensor"));
  expectSameSpinning(model, loaded);
  // The loaded model reads a frame as the fitted one does.
  const Scan& s = quantisedScan();
  const RangeImage a = pcl::patchdict::makeRangeImage(s.points, model.spinning);
  const RangeImage b = pcl::patchdict::makeRangeImage(s.points, loaded.spinning);
  EXPECT_EQ(0, std::memcmp(a.range.data(), b.range.data(), a.range.size() * sizeof(double)));
  EXPECT_THROW(pcl::patchdict::loadSensorModel(dir.file("missing.sensor")), pcl::patchdict::Error);
  EXPECT_THROW(pcl::patchdict::formatSensorModel(SensorModel{}), pcl::patchdict::Error);
}

// The text with the line of `key` replaced by `line` ("" removes it).
std::string withLine(const std::string& text, const std::string& key, const std::string& line)
{
  std::string out;
  std::size_t start = 0;
  bool found = false;
  while (start < text.size()) {
    const std::size_t end = text.find('\n', start);
    const std::string current = text.substr(start, end - start);
    if (current.compare(0, key.size() + 1, key + " ") == 0) {
      found = true;
      if (!line.empty())
        out += line + "\n";
    } else {
      out += current + "\n";
    }
    start = end == std::string::npos ? text.size() : end + 1;
  }
  EXPECT_TRUE(found) << key;
  return out;
}

TEST(SensorModelText, ParseRejectsEverythingElse)
{
  const SensorModel model = spinningModel();
  const std::string text = pcl::patchdict::formatSensorModel(model);
  ASSERT_NO_THROW(pcl::patchdict::parseSensorModel(text));
  std::string elevations = "elevation", fewer = "elevation", swapped = "elevation", offsets_nan = "azimuth_offset";
  for (std::size_t b = 0; b < model.height; ++b) {
    char number[40];
    std::snprintf(number, sizeof number, " %.17g", model.spinning.elevation[b]);
    elevations += number;
    if (b + 1 < model.height)
      fewer += number;
    std::snprintf(number, sizeof number, " %.17g",
                  model.spinning.elevation[b == 5 ? 6 : b == 6 ? 5 : b]);
    swapped += number;
    offsets_nan += b == 3 ? " nan" : " 0";
  }
  ASSERT_EQ(withLine(text, "elevation", elevations), text);  // the helper rebuilds the text exactly
  const std::vector<std::pair<const char*, std::string>> bad = {
      {"empty", ""},
      {"garbage", "hello world\n"},
      {"binary", std::string("\0\1\2\3", 4)},
      {"wrong magic", "pcl_patchdict sensor model 2\n" + text.substr(text.find('\n') + 1)},
      {"no elevation", withLine(text, "elevation", "")},
      {"no range_noise", withLine(text, "range_noise", "")},
      {"no width", withLine(text, "width", "")},
      {"fewer elevations", withLine(text, "elevation", fewer)},
      {"more elevations", withLine(text, "elevation", elevations + " -0.5")},
      {"azimuth count", withLine(text, "azimuth", "azimuth 3.1")},
      {"non-monotonic", withLine(text, "elevation", swapped)},
      {"NaN offset", withLine(text, "azimuth_offset", offsets_nan)},
      {"NaN step", withLine(text, "azimuth", "azimuth 3.1 nan")},
      {"inf radius", withLine(text, "beam_origin", "beam_origin inf 0.036")},
      {"word", withLine(text, "beam_origin", "beam_origin 0.0158 high")},
      {"trailing junk", withLine(text, "beam_origin", "beam_origin 0.0158 0.036x")},
      {"zero step", withLine(text, "azimuth", "azimuth 3.1 0")},
      {"two turns", withLine(text, "azimuth", "azimuth 3.1 -0.0245")},
      {"negative noise", withLine(text, "range_noise", "range_noise -0.01 0 0")},
      {"fractional width", withLine(text, "width", "width 512.5")},
      {"negative height", withLine(text, "height", "height -32")},
      {"unknown kind", withLine(text, "kind", "kind lidar")},
      {"duplicate key", text + "wraps 1\n"},
  };
  for (const auto& [what, input] : bad) {
    try {
      pcl::patchdict::parseSensorModel(input);
      ADD_FAILURE() << what << ": accepted";
    } catch (const pcl::patchdict::Error& e) {
      EXPECT_FALSE(std::string(e.what()).empty()) << what;
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << what << ": " << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": not a pcl::patchdict::Error: " << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// GeometricCloudInpainter<pcl::PointXYZI> on spinning-LiDAR frames

using Inpainter = pcl::patchdict::GeometricCloudInpainter<pcl::PointXYZI>;

/** The scan as an organised cloud (width = columns, height = beams); intensity 100 where measured,
  * 0 where not. */
pcl::PointCloud<pcl::PointXYZI>::Ptr cloudOf(const Scan& s)
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZI>>(static_cast<std::uint32_t>(s.W),
                                                                  static_cast<std::uint32_t>(s.H));
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    auto& p = (*cloud)[i];
    p.getVector3fMap() = s.points[i].cast<float>();
    p.intensity = s.points[i].allFinite() ? 100.0f : 0.0f;
  }
  cloud->is_dense = false;
  return cloud;
}

TEST(RangeImageInpainter, CompleteFillsWallDropoutsInPlaceAndReusesTheSensorModel)
{
  Scan s = noisyScan();
  std::vector<std::size_t> punched;
  for (const Hole& h : kWallHoles) {
    const auto pixels = s.disc(h.row, h.column, h.radius);
    s.erase(pixels);
    punched.insert(punched.end(), pixels.begin(), pixels.end());
  }
  s.erase(s.disc(kEdgeHole.row, kEdgeHole.column, kEdgeHole.radius));
  std::sort(punched.begin(), punched.end());
  const auto cloud = cloudOf(s);
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(Inpainter::Mode::Complete);
  inpainter.setNumberOfThreads(2);
  pcl::PointCloud<pcl::PointXYZI> out;
  inpainter.process(out);
  const auto& report = inpainter.getReport();
  ASSERT_TRUE(report.range_image);
  EXPECT_FALSE(report.depth_image);
  EXPECT_FALSE(report.sensor_model_given);
  EXPECT_TRUE(report.spinning.valid);
  EXPECT_EQ(report.input_points, s.points.size());
  EXPECT_EQ(out.width, s.W);
  EXPECT_EQ(out.height, s.H);
  EXPECT_EQ(out.size(), cloud->size());
  std::vector<std::size_t> filled;
  for (const auto i : inpainter.getAddedSources())
    filled.push_back(static_cast<std::size_t>(i));
  EXPECT_EQ(filled, punched);
  EXPECT_EQ(report.points_added, punched.size());
  EXPECT_EQ(report.range_fill.holes_filled, 4u);
  double sum = 0.0;
  for (const std::size_t i : filled) {
    const Eigen::Vector3d p = out[i].getVector3fMap().cast<double>();
    const Eigen::Vector3d truth = s.sensor.pointAt(i / s.W, i % s.W, s.truth[i]);
    sum += (p - truth).norm();
    EXPECT_NEAR(out[i].intensity, 100.0f, 1e-3f) << i;  // from the neighbours, not the pixel's own 0
  }
  const double mean = sum / double(std::max<std::size_t>(1, filled.size()));
  std::printf("[ observed ] inpainter fill: %zu points, mean distance to the truth %.4g m, %.3f s in the model\n",
              filled.size(), mean, report.seconds_sensor_model);
  EXPECT_LT(mean, 1.5 * 0.01);  // observed 4.7 mm
  // Every measured point is the input's, bit for bit; the rest (sky, the edge's hole) NaN.
  std::size_t same = 0, measured = 0, nan = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (std::isfinite((*cloud)[i].x)) {
      ++measured;
      same += out[i].x == (*cloud)[i].x && out[i].y == (*cloud)[i].y && out[i].z == (*cloud)[i].z &&
              out[i].intensity == (*cloud)[i].intensity;
    } else if (!std::binary_search(punched.begin(), punched.end(), i)) {
      nan += std::isnan(out[i].x) && std::isnan(out[i].y) && std::isnan(out[i].z);
      EXPECT_EQ(out[i].intensity, 0.0f);
    }
  }
  EXPECT_EQ(same, measured);
  EXPECT_EQ(nan, out.size() - measured - punched.size());

  // The model of the frame, and a second frame of the same sensor processed on it.
  const SensorModel model = inpainter.getSensorModel();
  ASSERT_EQ(model.kind, SensorModel::Kind::Spinning);
  EXPECT_EQ(model.width, s.W);
  EXPECT_EQ(model.height, s.H);
  EXPECT_NEAR(model.spinning.beam_radius, 0.0158, 1e-3);
  Scan second = scan(trueSensor(), 0.01, 0.0, 77);
  const auto hole = second.disc(11, 250, 2.0);
  second.erase(hole);
  Inpainter stream;
  stream.setSensorModel(model);
  stream.setInputCloud(cloudOf(second));
  stream.setMode(Inpainter::Mode::Complete);
  pcl::PointCloud<pcl::PointXYZI> out2;
  stream.process(out2);
  EXPECT_TRUE(stream.getReport().sensor_model_given);
  EXPECT_TRUE(stream.getReport().range_image);
  EXPECT_EQ(stream.getSensorModel().kind, SensorModel::Kind::Spinning);
  EXPECT_EQ(stream.getSensorModel().spinning.elevation, model.spinning.elevation);
  std::vector<std::size_t> filled2;
  for (const auto i : stream.getAddedSources())
    filled2.push_back(static_cast<std::size_t>(i));
  EXPECT_EQ(filled2, hole);
  EXPECT_EQ(out2.width, second.W);
  EXPECT_EQ(out2.height, second.H);

  // Frames that do not fit the model: another width, another sensor's elevations.
  stream.setInputCloud(cloudOf(scan(trueSensor(256, 32), 0.01, 0.0, 78)));
  EXPECT_THROW(stream.process(out2), pcl::patchdict::Error);
  stream.setInputCloud(cloudOf(scan(trueSensor(512, 32, 22.5), 0.01, 0.0, 79)));
  EXPECT_THROW(stream.process(out2), pcl::patchdict::Error);
  // Without the model the other sensor's frame is fitted afresh.
  stream.clearSensorModel();
  stream.process(out2);
  EXPECT_TRUE(stream.getReport().range_image);
  EXPECT_FALSE(stream.getReport().sensor_model_given);
  EXPECT_NEAR(stream.getSensorModel().spinning.elevation[0], degrees(22.5), 1e-3);
}

TEST(RangeImageInpainter, DenoiseMovesPointsAlongTheirRaysAndKeepsTheGrid)
{
  const Scan& s = noisyScan();
  const auto cloud = cloudOf(s);
  Inpainter inpainter;
  inpainter.setInputCloud(cloud);
  inpainter.setMode(Inpainter::Mode::Denoise);
  pcl::PointCloud<pcl::PointXYZI> out;
  inpainter.process(out);
  const auto& report = inpainter.getReport();
  ASSERT_TRUE(report.range_image);
  EXPECT_EQ(out.width, s.W);
  EXPECT_EQ(out.height, s.H);
  double before = 0.0, after = 0.0, off_ray = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite((*cloud)[i].x)) {
      EXPECT_FALSE(std::isfinite(out[i].x));
      continue;
    }
    ASSERT_TRUE(std::isfinite(out[i].x)) << i;
    EXPECT_EQ(out[i].intensity, 100.0f);
    const Eigen::Vector3d truth = s.sensor.pointAt(i / s.W, i % s.W, s.truth[i]);
    const Eigen::Vector3d p = out[i].getVector3fMap().cast<double>(), q = (*cloud)[i].getVector3fMap().cast<double>();
    // Along the measured point's ray from its beam's origin.
    const Eigen::Vector3d o = s.sensor.rayOrigin(i / s.W, i % s.W);
    off_ray = std::max(off_ray, (p - o).normalized().cross((q - o).normalized()).norm());
    if (s.surface[i] != kBox && onOneSurface(s, i, 1, 3)) {
      before += (q - truth).squaredNorm();
      after += (p - truth).squaredNorm();
      ++count;
    }
  }
  std::printf("[ observed ] inpainter denoise: rms %.4g -> %.4g m over %zu plane points, largest turn %.3g rad\n",
              std::sqrt(before / double(count)), std::sqrt(after / double(count)), count, off_ray);
  EXPECT_GT(std::sqrt(before / after), 1.5);
  EXPECT_LT(off_ray, 1e-5);
}

}  // namespace
