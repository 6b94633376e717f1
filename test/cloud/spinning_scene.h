// Test support: a synthetic Ouster-like spinning sensor (32 beams, 512 columns, negative azimuth step,
// per-beam azimuth offsets, beam origins on a 15.8 mm circle 36 mm up) ray-cast into a closed room
// with a box, its ranges noisy (σ = 1 cm, optionally stored in 8 mm steps), with the truth kept.
#pragma once

#include <pcl_patchdict/cloud/geometric_cloud_repair.h>
#include <pcl_patchdict/cloud/range_image.h>
#include <pcl_patchdict/cloud/range_image_repair.h>
#include <pcl_patchdict/cloud/sensor_model.h>
#include <pcl_patchdict/core/error.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

namespace spinning_scene {

using pcl::patchdict::RangeImage;
using pcl::patchdict::RangeNoiseModel;
using pcl::patchdict::SensorModel;
using pcl::patchdict::SpinningSensorModel;

constexpr double kPi = 3.14159265358979323846;
inline const double kNaN = std::numeric_limits<double>::quiet_NaN();
inline const double kInf = std::numeric_limits<double>::infinity();

inline double degrees(double d) { return d * kPi / 180.0; }

inline double wrap(double a)
{
  a = std::fmod(a + kPi, 2.0 * kPi);
  return a < 0.0 ? a + kPi : a - kPi;
}

// Surfaces of the room, as labelled by the ray caster.
enum Surface { kSky = -1, kGround = 0, kFrontWall = 1, kBackWall = 2, kLeftWall = 3, kRightWall = 4, kBox = 5 };

/** The true sensor: 32 beams from +15° to −15° (row 0 up, slightly uneven), 512 columns over a whole
  * turn with a negative step (Ouster's), column 0 looking backwards, beam offsets of ±0.03°. */
inline SpinningSensorModel trueSensor(std::size_t width = 512, std::size_t height = 32, double top = 15.0)
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
inline double castRay(const Eigen::Vector3d& o, const Eigen::Vector3d& u, int& surface)
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

inline Scan scan(const SpinningSensorModel& sensor, double sigma, double quantum, unsigned seed, double angle_jitter = 0.0)
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
inline bool onOneSurface(const Scan& s, std::size_t i, int rows, int columns)
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
inline const Scan& noisyScan()
{
  static const Scan s = scan(trueSensor(), 0.01, 0.0, 11);
  return s;
}
inline const Scan& quantisedScan()
{
  static const Scan s = scan(trueSensor(), 0.01, 0.008, 12);
  return s;
}

inline RangeImage imageOf(const std::vector<Eigen::Vector3d>& points, const SpinningSensorModel& model)
{
  return pcl::patchdict::makeRangeImage(points, model);
}

}  // namespace spinning_scene
