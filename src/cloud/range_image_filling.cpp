// fillRangeImageHoles (range_image_repair.h): dropouts of a spinning LiDAR's range image enclosed by
// one surface, filled on their pixels' rays by the rim's plane plus its harmonic misfit.
#include "cloud/range_plane.h"

#include <pcl_patchdict/cloud/range_image_repair.h>
#include <pcl_patchdict/core/error.h>

#include <Eigen/Sparse>

#include <algorithm>
#include <functional>
#include <cmath>
#include <limits>

namespace pcl {
namespace patchdict {

namespace {

/// The grid's 4-neighbours: the azimuth wraps when the model does; beams never do.
struct Grid {
  std::size_t W, H;
  bool wraps;
  template <typename F>
  void forNeighbours(std::size_t i, F&& f) const
  {
    const std::size_t b = i / W, c = i % W;
    if (b > 0)
      f(i - W);
    if (b + 1 < H)
      f(i + W);
    if (c > 0 || wraps)
      f(b * W + (c + W - 1) % W);
    if (c + 1 < W || wraps)
      f(b * W + (c + 1) % W);
  }
  bool onBorder(std::size_t i) const
  {
    const std::size_t b = i / W, c = i % W;
    return b == 0 || b + 1 == H || (!wraps && (c == 0 || c + 1 == W));
  }
};

struct Region {
  std::vector<std::size_t> pixels;
  bool border = false;
};

// 4-connected regions of unmeasured pixels, each region's pixels in row-major order.
std::vector<Region> emptyRegions(const RangeImage& image, const Grid& grid)
{
  const std::size_t n = grid.W * grid.H;
  std::vector<char> seen(n, 0);
  std::vector<Region> regions;
  std::vector<std::size_t> stack;
  for (std::size_t s = 0; s < n; ++s) {
    if (image.valid[s] || seen[s])
      continue;
    Region region;
    seen[s] = 1;
    stack.assign(1, s);
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      region.pixels.push_back(i);
      region.border = region.border || grid.onBorder(i);
      grid.forNeighbours(i, [&](std::size_t j) {
        if (!image.valid[j] && !seen[j]) {
          seen[j] = 1;
          stack.push_back(j);
        }
      });
    }
    std::sort(region.pixels.begin(), region.pixels.end());
    regions.push_back(std::move(region));
  }
  return regions;
}

// Measured pixels within `depth` 4-steps of the region: the ring (first layer = the rim).
void ringAround(const RangeImage& image, const Grid& grid, const Region& region, int depth,
                std::vector<std::size_t>& ring, std::size_t& rim_size, std::vector<int>& mark, int stamp)
{
  ring.clear();
  std::vector<std::size_t> front = region.pixels, next;
  for (const std::size_t i : region.pixels)
    mark[i] = stamp;
  for (int layer = 0; layer < depth && !front.empty(); ++layer) {
    next.clear();
    for (const std::size_t i : front)
      grid.forNeighbours(i, [&](std::size_t j) {
        if (mark[j] != stamp && image.valid[j]) {
          mark[j] = stamp;
          next.push_back(j);
        }
      });
    std::sort(next.begin(), next.end());
    ring.insert(ring.end(), next.begin(), next.end());
    if (layer == 0)
      rim_size = next.size();
    front = next;
  }
}

// The rim's ranges span at most `spread` of their median.
bool narrowRim(const RangeImage& image, const std::vector<std::size_t>& rim, double spread)
{
  std::vector<double> ranges;
  for (const std::size_t j : rim)
    ranges.push_back(image.range[j]);
  const auto extremes = std::minmax_element(ranges.begin(), ranges.end());
  const double width = *extremes.second - *extremes.first;
  std::nth_element(ranges.begin(), ranges.begin() + std::ptrdiff_t(ranges.size() / 2), ranges.end());
  return width <= spread * ranges[ranges.size() / 2];
}

double tukey(double r)
{
  if (std::abs(r) >= 1.0)
    return 0.0;
  const double t = 1.0 - r * r;
  return t * t;
}

/// The plane of a region's ring in 1/ρ (w: n/d in the basis), fitted three times, the last two with
/// Tukey weights of the range misfit; false when it fails or faces away.
bool fitRingPlane(const RangeImage& image, const RangeNoiseModel& noise, const std::vector<std::size_t>& ring,
                  std::size_t rim_size, const detail::RayBasis& basis, const std::function<double(double)>& tau,
                  Eigen::Vector3d& w)
{
  double reference = 0.0;
  for (std::size_t q = 0; q < rim_size; ++q)
    reference += image.range[ring[q]] / double(rim_size);
  w = Eigen::Vector3d::Zero();
  for (int pass = 0; pass < 3; ++pass) {
    detail::InverseRangePlane plane;
    for (const std::size_t j : ring) {
      const double r = image.range[j], s = noise.sigma(r) > 0.0 ? noise.sigma(r) : 0.01 * r;
      const Eigen::Vector3d x = basis.coordinates(image.direction(j));
      double weight = (r / reference) * (r / reference) * (r / reference) * (r / reference) / (s * s);
      if (pass > 0)
        weight *= tukey((r - 1.0 / w.dot(x)) / (2.0 * tau(r)));
      if (weight > 0.0)
        plane.add(x, 1.0 / r, weight);
    }
    if (!(plane.solve(w) && w(0) > 0.0))
      return false;
  }
  return true;
}

/// Whether the rim's points span more than `max_diameter` (twice the farthest from their mean).
bool rimWiderThan(const RangeImage& image, const std::vector<std::size_t>& ring, std::size_t rim_size,
                  double max_diameter)
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> rim_points;
  for (std::size_t q = 0; q < rim_size; ++q) {
    const std::size_t j = ring[q];
    rim_points.push_back(image.pointAt(j, image.range[j]));
    mean += rim_points.back() / double(rim_size);
  }
  double widest = 0.0;
  for (const auto& x : rim_points)
    widest = std::max(widest, 2.0 * (x - mean).norm());
  return widest > max_diameter;
}

/// The rim's misfit, harmonic inside the region (Dirichlet at the rim): L m = Σ rim neighbours'
/// misfits. `mark` numbers the region's pixels −2 − q while it runs (restored by the caller).
Eigen::VectorXd harmonicMisfit(const Grid& grid, const Region& region, const std::vector<std::size_t>& ring,
                               const std::vector<double>& misfit, std::vector<int>& mark, std::vector<double>& rim_misfit)
{
  const std::size_t m = region.pixels.size();
  for (std::size_t q = 0; q < m; ++q)
    mark[region.pixels[q]] = -2 - static_cast<int>(q);  // the region's own numbering
  for (std::size_t q = 0; q < misfit.size(); ++q)
    rim_misfit[ring[q]] = misfit[q];
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m));
  for (std::size_t q = 0; q < m; ++q) {
    double degree = 0.0;
    grid.forNeighbours(region.pixels[q], [&](std::size_t j) {
      degree += 1.0;
      if (mark[j] <= -2)
        entries.emplace_back(Eigen::Index(q), Eigen::Index(-2 - mark[j]), -1.0);
      else
        rhs(Eigen::Index(q)) += rim_misfit[j];
    });
    entries.emplace_back(Eigen::Index(q), Eigen::Index(q), degree);
  }
  const Eigen::Index size = static_cast<Eigen::Index>(m);
  Eigen::SparseMatrix<double> L(size, size);
  L.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(L);
  Eigen::VectorXd correction = solver.solve(rhs);
  if (solver.info() != Eigen::Success || !correction.allFinite())
    correction.setZero();
  return correction;
}

}  // namespace

void fillRangeImageHoles(const RangeImage& image, const RangeNoiseModel& noise, const RangeFillParameters& parameters,
                         std::vector<std::size_t>& pixels, std::vector<double>& ranges, RangeFillReport& report)
{
  const RangeFillParameters& p = parameters;
  if (p.max_hole_pixels == 0 || !(p.max_hole_diameter >= 0.0) || !(p.rim_noise_factor > 0.0) ||
      !(p.rim_relative_range >= 0.0) || !(p.rim_spread > 0.0) || !(p.max_incidence_degrees > 0.0) ||
      !(p.max_incidence_degrees <= 90.0) || p.fit_ring < 0 || p.fit_ring > 64 || !(p.free_space_spacing >= 0.0) ||
      !(p.free_space_relative >= 0.0))
    throw Error("range fill parameters out of range");
  const Grid grid{image.width, image.height, image.model.wraps};
  const double step = std::abs(image.model.azimuth_step);
  const std::vector<double> nearest = nearestMeasuredRange(image);
  const OriginFreeSpace from_origin(image, p.free_space_spacing, p.free_space_relative);
  std::vector<int> mark(image.width * image.height, -1);
  std::vector<std::size_t> ring;
  std::vector<double> rim_misfit(image.width * image.height, 0.0);  // set on each region's rim in turn
  const std::vector<Region> regions = emptyRegions(image, grid);
  report.regions += regions.size();
  const auto tau = [&](double r) { return std::max(p.rim_noise_factor * noise.sigma(r), p.rim_relative_range * r); };
  std::vector<std::pair<std::size_t, double>> filled;
  for (std::size_t k = 0; k < regions.size(); ++k) {
    const Region& region = regions[k];
    if (region.border) {
      ++report.touching_border;
      continue;
    }
    if (region.pixels.size() > p.max_hole_pixels) {
      ++report.too_large;
      continue;
    }
    // One surface: the rim continuous, its ranges within rim_spread of their median (a range
    // discontinuity — an object before a wall, sky — spreads it far more). Tested on the rim alone
    // first: most regions of a frame fail it, and cheaply.
    std::size_t rim_size = 0;
    ringAround(image, grid, region, 1, ring, rim_size, mark, static_cast<int>(k));
    if (rim_size < 3 || !narrowRim(image, ring, p.rim_spread)) {
      ++report.not_one_surface;
      continue;
    }
    const int radius = static_cast<int>(std::lround(std::sqrt(double(region.pixels.size()) / 3.14159265)));
    ringAround(image, grid, region, p.fit_ring > 0 ? p.fit_ring : std::clamp(radius, 2, 6), ring, rim_size, mark,
               static_cast<int>(k) + static_cast<int>(regions.size()));
    // The plane of the ring, about the region's mean ray.
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const std::size_t i : region.pixels)
      centre += image.direction(i);
    const detail::RayBasis basis(centre.normalized(), step);
    Eigen::Vector3d w;
    bool one_surface = fitRingPlane(image, noise, ring, rim_size, basis, tau, w);  // and a plane through the ring
    std::vector<double> misfit(rim_size, 0.0);
    for (std::size_t q = 0; q < rim_size && one_surface; ++q) {
      const double predicted = 1.0 / w.dot(basis.coordinates(image.direction(ring[q])));
      misfit[q] = image.range[ring[q]] - predicted;
      one_surface = predicted > 0.0;
    }
    if (!one_surface) {
      ++report.not_one_surface;
      continue;
    }
    // The plane's normal (w = n/d in the basis): at grazing incidence a small error of angle is a
    // large error of range (dρ/dθ = ρ·tan i), and the fill is no longer determined by its rim.
    const Eigen::Vector3d normal = w(0) * basis.u + (w(1) / step) * basis.e1 + (w(2) / step) * basis.e2;
    if (std::abs(normal.dot(basis.u)) < std::cos(p.max_incidence_degrees * 3.14159265358979323846 / 180.0) * normal.norm()) {
      ++report.grazing;
      continue;
    }
    if (p.max_hole_diameter > 0.0 && rimWiderThan(image, ring, rim_size, p.max_hole_diameter)) {
      ++report.too_large;
      continue;
    }
    const Eigen::VectorXd correction = harmonicMisfit(grid, region, ring, misfit, mark, rim_misfit);
    const std::size_t m = region.pixels.size();
    for (std::size_t q = 0; q < m; ++q) {
      const std::size_t i = region.pixels[q];
      mark[i] = static_cast<int>(k);
      double r = 1.0 / w.dot(basis.coordinates(image.direction(i))) + correction(Eigen::Index(q));
      if (!(r > 0.0) || !std::isfinite(r))
        continue;
      // A fill the beams contradict is left open, not pushed off its surface to where they allow.
      const double least = freeSpaceBound(nearest[i], image.model.azimuth_step, p.free_space_spacing, p.free_space_relative);
      if (r < least || from_origin.violates(image.pointAt(i, r), i)) {
        ++report.free_space_dropped;
        continue;
      }
      filled.emplace_back(i, r);
    }
    ++report.holes_filled;
  }
  std::sort(filled.begin(), filled.end());
  for (const auto& f : filled) {
    pixels.push_back(f.first);
    ranges.push_back(f.second);
  }
  report.pixels_filled += filled.size();
}

}  // namespace patchdict
}  // namespace pcl
